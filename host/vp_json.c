/* vp_json — see vp_json.h. */
#include "vp_json.h"

void vp_json_str(FILE *f, const char *s, int html)
{
    fputc('"', f);
    for (; *s; s++) {
        unsigned char c = (unsigned char)*s;
        if (c == '"' || c == '\\') fprintf(f, "\\%c", c);
        else if (c < 0x20 || (html && (c == '<' || c == '>' || c == '&'))) fprintf(f, "\\u%04x", c);
        else fputc(c, f);
    }
    fputc('"', f);
}
