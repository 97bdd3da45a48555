/* Chi-square goodness-of-fit of direction samplers (see chi2.h). */
#include <math.h>
#include <stdlib.h>
#include "chi2.h"
#include "restir/core/rng.h"

#define CHI2_PI 3.14159265358979323846
/* Absolute quadrature tolerance per cell (probability units). The float build's pdf
 * carries ~1e-7 relative rounding noise that adaptive Simpson cannot beat, so it
 * stops earlier (0.1 count of 10^6 samples per cell). */
#define CHI2_TOL (sizeof(real) == 8 ? 1e-9 : 1e-7)

typedef struct {
    const chi2_config *cfg;
    double t[3], b[3], c[3]; /* frame around the centre */
} zoom_frame;

static void make_frame(zoom_frame *f, const chi2_config *cfg)
{
    vec3 c = v3_normalize(cfg->center), t, b;
    v3_basis(c, &t, &b);
    f->cfg = cfg;
    f->t[0] = t.x; f->t[1] = t.y; f->t[2] = t.z;
    f->b[0] = b.x; f->b[1] = b.y; f->b[2] = b.z;
    f->c[0] = c.x; f->c[1] = c.y; f->c[2] = c.z;
}

/* Direction of zoomed coordinates (a, phi) and the Jacobian d omega / (da dphi).
 * With q = (1-a) + k^2 a: cos = ((1-a) - k^2 a)/q, sin = 2k sqrt(a(1-a))/q, J = 2k^2/q^2. */
static void direction_of(const zoom_frame *f, double a, double phi, double w[3], double *jac)
{
    double k = f->cfg->zoom, q = (1 - a) + k * k * a;
    double ct = ((1 - a) - k * k * a) / q, st = 2 * k * sqrt(a * (1 - a)) / q;
    double x = st * cos(phi), y = st * sin(phi);
    int i;
    for (i = 0; i < 3; ++i) w[i] = x * f->t[i] + y * f->b[i] + ct * f->c[i];
    *jac = 2 * k * k / (q * q);
}

/* Inverse: a = |w-c|^2 / (|w-c|^2 + k^2 |w+c|^2), exact near the pole. */
static void coords_of(const zoom_frame *f, vec3 wr, double *a, double *phi)
{
    double w[3] = {wr.x, wr.y, wr.z}, dm = 0, dp = 0, x = 0, y = 0, k = f->cfg->zoom, n;
    int i;
    n = sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
    for (i = 0; i < 3; ++i) {
        w[i] /= n;
        dm += (w[i] - f->c[i]) * (w[i] - f->c[i]);
        dp += (w[i] + f->c[i]) * (w[i] + f->c[i]);
        x += w[i] * f->t[i];
        y += w[i] * f->b[i];
    }
    *a = dm / (dm + k * k * dp);
    *phi = atan2(y, x);
    if (*phi < 0) *phi += 2 * CHI2_PI;
}

static double density(const zoom_frame *f, double a, double phi)
{
    double w[3], jac, p;
    direction_of(f, a, phi, w, &jac);
    p = f->cfg->pdf(f->cfg->ctx, v3((real)w[0], (real)w[1], (real)w[2]));
    return p * jac;
}

/* ---- nested adaptive Simpson ---- */
typedef struct {
    const zoom_frame *f;
    double a;          /* fixed outer coordinate for the inner integral */
    double phi0, phi1; /* inner range */
} simpson_ctx;

typedef double (*integrand)(const simpson_ctx *s, double x);

static double adaptive(integrand g, const simpson_ctx *s, double x0, double x1, double g0, double gm, double g1,
                       double whole, double tol, int depth)
{
    double m = 0.5 * (x0 + x1), l = 0.5 * (x0 + m), r = 0.5 * (m + x1);
    double gl = g(s, l), gr = g(s, r);
    double left = (m - x0) / 6 * (g0 + 4 * gl + gm), right = (x1 - m) / 6 * (gm + 4 * gr + g1);
    if (depth <= 0 || fabs(left + right - whole) <= 15 * tol) return left + right + (left + right - whole) / 15;
    return adaptive(g, s, x0, m, g0, gl, gm, left, tol / 2, depth - 1) +
           adaptive(g, s, m, x1, gm, gr, g1, right, tol / 2, depth - 1);
}

/* Integral over [x0, x1], split first into `pieces` so narrow peaks are seen. */
static double integrate(integrand g, const simpson_ctx *s, double x0, double x1, double tol, int pieces)
{
    double sum = 0, h = (x1 - x0) / pieces;
    int i;
    for (i = 0; i < pieces; ++i) {
        double a = x0 + i * h, b = a + h, ga = g(s, a), gm = g(s, a + h / 2), gb = g(s, b);
        sum += adaptive(g, s, a, b, ga, gm, gb, h / 6 * (ga + 4 * gm + gb), tol / pieces, 10);
    }
    return sum;
}

static double inner(const simpson_ctx *s, double phi) { return density(s->f, s->a, phi); }

static double outer(const simpson_ctx *s, double a)
{
    simpson_ctx in = *s;
    in.a = a;
    return integrate(inner, &in, s->phi0, s->phi1, CHI2_TOL / 10, 4);
}

static double cell_integral(const zoom_frame *f, double a0, double a1, double phi0, double phi1)
{
    simpson_ctx s;
    s.f = f;
    s.a = 0;
    s.phi0 = phi0;
    s.phi1 = phi1;
    return integrate(outer, &s, a0, a1, CHI2_TOL, 4);
}

/* ---- the test ---- */

static void count_samples(const chi2_config *cfg, const zoom_frame *f, double *observed, long *rejected)
{
    long i;
    for (i = 0; i < cfg->samples; ++i) {
        rng_key k = rng_key_at(rng_key_make(cfg->seed, cfg->stream, (uint32_t)i), RNG_TEST, 0, 0);
        vec2 u = v2((real)rng_uniform_double(k), (real)rng_uniform_double(rng_key_at(k, RNG_TEST, 0, 1)));
        vec3 w;
        double a, phi;
        int ia, ip;
        if (!cfg->sample(cfg->ctx, u, &w)) {
            ++*rejected;
            continue;
        }
        coords_of(f, w, &a, &phi);
        ia = (int)(a * cfg->n_a);
        ip = (int)(phi / (2 * CHI2_PI) * cfg->n_phi);
        ia = ia < 0 ? 0 : (ia >= cfg->n_a ? cfg->n_a - 1 : ia);
        ip = ip < 0 ? 0 : (ip >= cfg->n_phi ? cfg->n_phi - 1 : ip);
        observed[ia * cfg->n_phi + ip] += 1;
    }
}

static void expected_counts(const chi2_config *cfg, const zoom_frame *f, double *expected)
{
    int ia, ip;
    for (ia = 0; ia < cfg->n_a; ++ia)
        for (ip = 0; ip < cfg->n_phi; ++ip) {
            double a0 = (double)ia / cfg->n_a, a1 = (double)(ia + 1) / cfg->n_a;
            double p0 = 2 * CHI2_PI * ip / cfg->n_phi, p1 = 2 * CHI2_PI * (ip + 1) / cfg->n_phi;
            expected[ia * cfg->n_phi + ip] = cfg->samples * cell_integral(f, a0, a1, p0, p1);
        }
}

/* Pearson's statistic with cells of expectation < 5 pooled (the last cell is the
 * rejection cell). */
static void pearson(const double *obs, const double *expd, int cells, chi2_result *res)
{
    double pool_obs = 0, pool_exp = 0, chi2 = 0;
    int i, used = 0;
    res->pooled_cells = 0;
    for (i = 0; i < cells; ++i) {
        if (expd[i] < 5) {
            pool_obs += obs[i];
            pool_exp += expd[i];
            res->pooled_cells++;
            continue;
        }
        chi2 += (obs[i] - expd[i]) * (obs[i] - expd[i]) / expd[i];
        used++;
    }
    if (pool_exp >= 5) {
        chi2 += (pool_obs - pool_exp) * (pool_obs - pool_exp) / pool_exp;
        used++;
    } else if (pool_obs > 20) {
        chi2 = HUGE_VAL; /* many samples where the pdf says (almost) none can land */
    }
    res->chi2 = chi2;
    res->dof = used - 1;
}

int chi2_run(const chi2_config *cfg, chi2_result *res)
{
    int cells = cfg->n_a * cfg->n_phi, i;
    double *obs = calloc((size_t)cells + 1, sizeof *obs), *expd = calloc((size_t)cells + 1, sizeof *expd);
    double total = 0;
    zoom_frame f;
    if (!obs || !expd) {
        free(obs);
        free(expd);
        return 1;
    }
    make_frame(&f, cfg);
    res->rejected = 0;
    count_samples(cfg, &f, obs, &res->rejected);
    expected_counts(cfg, &f, expd);
    for (i = 0; i < cells; ++i) total += expd[i];
    res->pdf_integral = total / cfg->samples;
    res->expected_rejected = cfg->samples - total > 0 ? cfg->samples - total : 0;
    obs[cells] = (double)res->rejected;
    expd[cells] = res->expected_rejected;
    pearson(obs, expd, cells + 1, res);
    /* dof = 0: all the mass in one cell (e.g. total internal reflection rejects
     * every sample); only the pooled remainder can then disagree. */
    if (res->dof > 0) res->p_value = chi2_survival(res->chi2, res->dof);
    else res->p_value = res->chi2 == HUGE_VAL ? 0 : 1;
    free(obs);
    free(expd);
    return 0;
}

/* ---- chi-square tail: regularised upper incomplete gamma Q(s, x) ---- */

/* Series for the lower function P(s, x), good for x < s + 1. */
static double gamma_p_series(double s, double x)
{
    double term = 1 / s, sum = term, n;
    for (n = 1; n < 1000; ++n) {
        term *= x / (s + n);
        sum += term;
        if (term < sum * 1e-16) break;
    }
    return sum * exp(-x + s * log(x) - lgamma(s));
}

/* Continued fraction for Q(s, x) (modified Lentz), good for x >= s + 1. */
static double gamma_q_fraction(double s, double x)
{
    double b = x + 1 - s, c = 1e300, d = 1 / b, h = d, n;
    for (n = 1; n < 1000; ++n) {
        double an = -n * (n - s), delta;
        b += 2;
        d = an * d + b;
        if (fabs(d) < 1e-300) d = 1e-300;
        c = b + an / c;
        if (fabs(c) < 1e-300) c = 1e-300;
        d = 1 / d;
        delta = d * c;
        h *= delta;
        if (fabs(delta - 1) < 1e-16) break;
    }
    return exp(-x + s * log(x) - lgamma(s)) * h;
}

double chi2_survival(double x, int dof)
{
    double s = 0.5 * dof, h = 0.5 * x;
    if (!(x > 0)) return x == HUGE_VAL ? 0 : 1;
    if (x == HUGE_VAL) return 0;
    return h < s + 1 ? 1 - gamma_p_series(s, h) : gamma_q_fraction(s, h);
}

double chi2_sidak(double alpha, int m) { return 1 - pow(1 - alpha, 1.0 / m); }
