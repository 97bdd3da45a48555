/* The options of the correlation remedies (include/restir/restir/correlation.h). */
#include "restir/restir/correlation.h"

#include <math.h>

void correlation_options_default(correlation_options *o)
{
    o->dedup = 0;
    o->dedup_min = 1; /* Enhanced §5: c_cap_min = 1, alpha = 0.1 */
    o->dedup_alpha = 0.1;
    o->boiling_filter = 0;
}

int correlation_options_validate(const correlation_options *o, rerror *e)
{
    if (o->dedup && (!(o->dedup_min > 0) || isinf(o->dedup_min)))
        return rerror_set(e, "correlation: dedup c_cap_min %g (must be finite and > 0)", o->dedup_min);
    if (o->dedup && (!(o->dedup_alpha > 0) || isinf(o->dedup_alpha)))
        return rerror_set(e, "correlation: dedup alpha %g (must be finite and > 0)", o->dedup_alpha);
    if (!(o->boiling_filter >= 0 && o->boiling_filter <= 1))
        return rerror_set(e, "correlation: boiling filter strength %g (in (0, 1], 0 = off)", o->boiling_filter);
    return 0;
}

int correlation_options_biased(const correlation_options *o) { return o->dedup || o->boiling_filter > 0; }
