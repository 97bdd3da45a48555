/* The RTXDI boiling filter (include/restir/restir/boiling_filter.h; Enhanced §7.4, Fig. 9). */
#include "restir/restir/boiling_filter.h"

double boiling_multiplier(double strength)
{
    double s = strength < 1e-6 ? 1e-6 : strength > 1 ? 1 : strength;
    return 10.0 / s - 9.0; /* Enhanced §7.4 */
}

int boiling_rejects(double w, double mean, double strength)
{
    return mean > 0 && w > boiling_multiplier(strength) * mean;
}

static double reservoir_weight(const reservoir *r)
{
    return path_sample_is_valid(&r->y) && r->W > 0 ? (double)r->y.target * (double)r->W : 0;
}

static uint64_t filter_group(reservoir *rs, int w, int x0, int y0, int x1, int y1, double strength)
{
    double sum = 0, mean;
    long n = 0;
    uint64_t cleared = 0;
    int x, y;
    for (y = y0; y < y1; ++y)
        for (x = x0; x < x1; ++x) {
            double wt = reservoir_weight(&rs[(long)y * w + x]);
            if (wt > 0) {
                sum += wt;
                ++n;
            }
        }
    if (n == 0) return 0;
    mean = sum / (double)n;
    for (y = y0; y < y1; ++y)
        for (x = x0; x < x1; ++x) {
            reservoir *r = &rs[(long)y * w + x];
            if (boiling_rejects(reservoir_weight(r), mean, strength)) {
                reservoir_init(r);
                ++cleared;
            }
        }
    return cleared;
}

uint64_t boiling_filter(reservoir *rs, int w, int h, int g, double strength)
{
    uint64_t cleared = 0;
    int x, y;
    for (y = 0; y < h; y += g)
        for (x = 0; x < w; x += g)
            cleared += filter_group(rs, w, x, y, x + g < w ? x + g : w, y + g < h ? y + g : h, strength);
    return cleared;
}
