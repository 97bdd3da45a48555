/* Sample identity and duplication maps (include/restir/duplication.h; Enhanced §5). */
#include "restir/duplication.h"

#include <math.h>

int duplication_same_sample(const reservoir *a, const reservoir *b)
{
    return a->W > 0 && b->W > 0 && path_sample_is_valid(&a->y) && path_sample_is_valid(&b->y) &&
           a->y.seed == b->y.seed && a->y.pixel == b->y.pixel && a->y.sample == b->y.sample;
}

/* Enhanced §5 step 1 at one pixel: copies of p's sample in its window, p excluded. */
static unsigned window_count(const reservoir *rs, int w, int h, int r, int x, int y)
{
    const reservoir *self = &rs[(long)y * w + x];
    unsigned n = 0;
    int i, j;
    if (!(self->W > 0)) return 0;
    for (j = y - r; j <= y + r; ++j) {
        if (j < 0 || j >= h) continue;
        for (i = x - r; i <= x + r; ++i)
            if (i >= 0 && i < w && (i != x || j != y) && duplication_same_sample(self, &rs[(long)j * w + i])) ++n;
    }
    return n;
}

void duplication_counts(const reservoir *rs, int w, int h, int r, uint16_t *count)
{
    int x, y;
    for (y = 0; y < h; ++y)
        for (x = 0; x < w; ++x) count[(long)y * w + x] = (uint16_t)window_count(rs, w, h, r, x, y);
}

double duplication_score_denominator(int r) { return (double)(2 * r + 1) * (double)(2 * r + 1) - 1; }

double duplication_score(unsigned count, int r)
{
    double d = (double)count / duplication_score_denominator(r);
    return d > 1 ? 1 : d;
}

/* Enhanced §5 step 3 */
double duplication_cap(double cap_default, double cap_min, double d, double alpha)
{
    double t = d > 0 ? pow(d, alpha) : 0;
    return cap_default + (cap_min - cap_default) * t;
}

void duplication_summarize(const uint16_t *count, long n, duplication_summary *s)
{
    long i;
    s->pixels = (uint64_t)n;
    s->duplicated = s->count_sum = 0;
    s->count_max = 0;
    for (i = 0; i < n; ++i) {
        s->duplicated += count[i] > 0;
        s->count_sum += count[i];
        if (count[i] > s->count_max) s->count_max = count[i];
    }
}

void duplication_summary_add(duplication_summary *acc, const duplication_summary *add)
{
    acc->pixels += add->pixels;
    acc->duplicated += add->duplicated;
    acc->count_sum += add->count_sum;
    if (add->count_max > acc->count_max) acc->count_max = add->count_max;
}

void duplication_heat_colour(double d, double d_max, unsigned char rgb[3])
{
    double t = d_max > 0 ? d / d_max : 1;
    if (!(t > 0)) t = 0;
    if (t > 1) t = 1;
    rgb[0] = (unsigned char)lround(255.0 * t);
    rgb[1] = rgb[2] = 0;
}
