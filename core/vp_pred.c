/* TEMPORARY naive predicates for development only (not exact). */
#include "vp_pred.h"
static int sgn(double x) { return (x > 0) - (x < 0); }
int vp_orient3d(const double *a, const double *b, const double *c, const double *d)
{
    double bx = b[0]-a[0], by = b[1]-a[1], bz = b[2]-a[2];
    double cx = c[0]-a[0], cy = c[1]-a[1], cz = c[2]-a[2];
    double dx = d[0]-a[0], dy = d[1]-a[1], dz = d[2]-a[2];
    return sgn(dx*(by*cz-bz*cy) + dy*(bz*cx-bx*cz) + dz*(bx*cy-by*cx));
}
int vp_insphere(const double *a, const double *b, const double *c, const double *d, const double *e)
{
    double m[4][4]; const double *p[4]; int i;
    p[0]=a;p[1]=b;p[2]=c;p[3]=d;
    for (i=0;i<4;i++){ m[i][0]=p[i][0]-e[0]; m[i][1]=p[i][1]-e[1]; m[i][2]=p[i][2]-e[2];
      m[i][3]=m[i][0]*m[i][0]+m[i][1]*m[i][1]+m[i][2]*m[i][2]; }
    {
    double det = 0; int r;
    for (r = 0; r < 4; r++) {
        int rows[3], k=0, q; double sub;
        for (q=0;q<4;q++) if (q!=r) rows[k++]=q;
        sub = m[rows[0]][0]*(m[rows[1]][1]*m[rows[2]][2]-m[rows[1]][2]*m[rows[2]][1])
            - m[rows[0]][1]*(m[rows[1]][0]*m[rows[2]][2]-m[rows[1]][2]*m[rows[2]][0])
            + m[rows[0]][2]*(m[rows[1]][0]*m[rows[2]][1]-m[rows[1]][1]*m[rows[2]][0]);
        det += ((r & 1) ? 1 : -1) * m[r][3] * sub;
    }
    return -sgn(det);
    }
}
int vp_lex_cmp(const double *a, const double *b)
{ int i; for (i=0;i<3;i++){ if (a[i]<b[i]) return -1; if (a[i]>b[i]) return 1;} return 0; }
int vp_insphere_sos(const double *a, const double *b, const double *c, const double *d, const double *e)
{
    int s = vp_insphere(a,b,c,d,e);
    const double *p[5]; int i, j;
    if (s) return s;
    p[0]=a;p[1]=b;p[2]=c;p[3]=d;p[4]=e;
    for (i = 0; i < 5; i++) for (j = i+1; j < 5; j++) if (vp_lex_cmp(p[j], p[i]) > 0) { const double *t=p[i]; p[i]=p[j]; p[j]=t; }
    for (i = 0; i < 5; i++) {
        int o;
        if (p[i] == e) return -1;
        if (p[i] == d && (o = vp_orient3d(a,b,c,e))) return o;
        if (p[i] == c && (o = vp_orient3d(a,b,e,d))) return o;
        if (p[i] == b && (o = vp_orient3d(a,e,c,d))) return o;
        if (p[i] == a && (o = vp_orient3d(e,b,c,d))) return o;
    }
    return 0;
}
int vp_orient2d_proj(const double *a, const double *b, const double *c, int drop)
{ int i=(drop+1)%3, j=(drop+2)%3; return sgn((b[i]-a[i])*(c[j]-a[j])-(b[j]-a[j])*(c[i]-a[i])); }
int vp_cmp_dist(const double *p, const double *q, const double *r)
{ double a=0,b=0; int i; for(i=0;i<3;i++){a+=(p[i]-q[i])*(p[i]-q[i]); b+=(p[i]-r[i])*(p[i]-r[i]);} return sgn(a-b); }
