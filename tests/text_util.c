/* text_util.h: numbers out of printed text (the bad_input rows are data only). */
#include "text_util.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

double json_after(const char **from, const char *key)
{
    char pattern[64];
    const char *p;
    snprintf(pattern, sizeof pattern, "\"%s\": ", key);
    p = strstr(*from, pattern);
    if (!p) return NAN;
    p += strlen(pattern);
    *from = p;
    return strtod(p, NULL);
}
