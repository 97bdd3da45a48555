/* Correlation under motion (docs/correlation.md): the options of the two BIASED remedies of
 * the real-time pipeline, the duplication-map adaptive temporal cap (Enhanced §5;
 * duplication.h) and the RTXDI boiling filter (boiling_filter.h). */
#ifndef RESTIR_CORRELATION_H
#define RESTIR_CORRELATION_H

#include "restir/core/error.h"

typedef struct {
    int dedup;             /* duplication-map adaptive cap (Enhanced §5): BIASED (default 0) */
    double dedup_min;      /* c_cap_min (default 1) */
    double dedup_alpha;    /* alpha of lerp(mcap, c_cap_min, D^alpha) (default 0.1) */
    double boiling_filter; /* strength s in (0, 1], 0 = off (default): BIASED */
} correlation_options;

void correlation_options_default(correlation_options *o);
/* 0, or -1 with "correlation: what is wrong". (That the adaptive cap needs a finite
 * temporal cap to lower is checked where both are known: restir_options_validate.) */
int correlation_options_validate(const correlation_options *o, rerror *e);
/* 1 if o turns on a remedy that is biased by design: the estimator is then no longer
 * unbiased (docs/correlation.md). */
int correlation_options_biased(const correlation_options *o);

#endif
