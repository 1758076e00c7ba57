/* vp_json — the one JSON string writer of the summaries (`scan --json`, `log dump --json`, the
 * report's data): the text in double quotes, '"' and '\' escaped, control characters as \uXXXX,
 * and with html != 0 also '<', '>' and '&' (a string that lands in a web page's script). */
#ifndef VP_JSON_H
#define VP_JSON_H
#include <stdio.h>

void vp_json_str(FILE *f, const char *s, int html);

#endif
