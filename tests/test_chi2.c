/* Chi-square goodness-of-fit of every non-delta BSDF lobe's sampler against its
 * pdf (tests/chi2.h, docs/materials.md §Chi-square). */
#include <stdio.h>
#include <stdlib.h>
#include <time.h>
#include "chi2.h"
#include "restir/scene/bsdf.h"
#include "restir/scene/microfacet.h"
#include "test.h"

#define CHI2_FAMILY_ALPHA 0.01
#define CHI2_SAMPLES 1000000L

/* CHI2_VERBOSE=1 prints every configuration's statistic. */
static int getenv_verbose(void) { return getenv("CHI2_VERBOSE") != NULL; }

typedef struct {
    bsdf b;
    int lobe;
    vec3 wo;
    int broken; /* test-only switch: claim a pdf 5% too high where w.x > 0 */
} lobe_case;

static int case_sample(void *ctx, vec2 u, vec3 *w)
{
    lobe_case *c = ctx;
    bsdf_sample_record s;
    if (!bsdf_lobe_sample(&c->b, c->lobe, c->wo, u, &s)) return 0;
    *w = s.wi;
    return 1;
}

static double case_pdf(void *ctx, vec3 w)
{
    lobe_case *c = ctx;
    double p = bsdf_lobe_pdf(&c->b, c->lobe, c->wo, w);
    return c->broken && w.x > 0 ? 1.05 * p : p;
}

static bsdf make_bsdf(enum material_type type, real roughness, real ior)
{
    material m;
    m.type = type;
    m.diffuse = rgb_gray((real)0.8);
    m.specular = rgb_gray(1);
    m.emission = rgb_gray(0);
    m.roughness = roughness;
    m.ior = ior;
    m.name[0] = 0;
    return bsdf_from_material(&m);
}

/* wo at cos theta = cos_o (negative: below, i.e. inside a dielectric), azimuth 0.3 rad. */
static vec3 wo_at(real cos_o)
{
    real s = (real)sqrt(fmax(0, 1 - cos_o * cos_o));
    return v3(s * (real)cos(0.3), s * (real)sin(0.3), cos_o);
}

/* Histogram pole and zoom for a lobe: the lobe's specular direction and k ~ 2 alpha. */
static void histogram_pole(const lobe_case *c, vec3 *center, double *zoom)
{
    enum bsdf_lobe_kind kind = bsdf_lobe_kind_of(&c->b, c->lobe);
    real side = c->wo.z > 0 ? 1 : -1;
    *zoom = 1;
    *center = v3(0, 0, side);
    if (kind == BSDF_LOBE_DIFFUSE) return;
    *zoom = fmin(1.0, 2.0 * c->b.alpha);
    if (kind == BSDF_LOBE_GLOSSY_REFLECTION) {
        *center = v3(-c->wo.x, -c->wo.y, c->wo.z);
    } else {
        real eta = side > 0 ? c->b.ior : 1 / c->b.ior;
        vec3 n = v3(0, 0, side), t;
        if (refract_about(c->wo, n, eta, &t)) {
            *center = t;
        } else { /* total internal reflection at the macro normal: only strongly tilted
                    microfacets transmit, anywhere on the far side: no zoom */
            *center = v3(0, 0, -side);
            *zoom = 1;
        }
    }
}

/* One configuration; returns its p-value (negative if the histogram failed). */
static double run_case(lobe_case *c, uint32_t stream, chi2_result *res)
{
    chi2_config cfg;
    cfg.sample = case_sample;
    cfg.pdf = case_pdf;
    cfg.ctx = c;
    histogram_pole(c, &cfg.center, &cfg.zoom);
    cfg.n_a = 10;
    cfg.n_phi = 20;
    cfg.samples = CHI2_SAMPLES;
    cfg.seed = test_seed();
    cfg.stream = stream;
    if (chi2_run(&cfg, res)) return -1;
    return res->p_value;
}

typedef struct {
    enum material_type type;
    int lobe;
    real roughness;
    real cos_o;
} chi2_case_spec;

static const char *type_name(enum material_type t)
{
    static const char *names[] = {"lambert", "conductor", "plastic", "dielectric", "rough_dielectric"};
    return names[t];
}

/* Runs a family of cases with Sidak-corrected significance; reports each. */
static int run_family(const chi2_case_spec *specs, int count, char *why, size_t why_size)
{
    double level = chi2_sidak(CHI2_FAMILY_ALPHA, count);
    int i;
    for (i = 0; i < count; ++i) {
        /* float build: grazing (|cos| < 0.05) histograms are dominated by the float pdf's
         * rounding near the horizon (chi2 ~1.5x its dof); the double oracle tests them */
        if (sizeof(real) < 8 && fabs(specs[i].cos_o) < 0.05) continue;
        lobe_case c;
        chi2_result res;
        double p;
        clock_t t0;
        c.b = make_bsdf(specs[i].type, specs[i].roughness, (real)1.5);
        c.lobe = specs[i].lobe;
        c.wo = wo_at(specs[i].cos_o);
        c.broken = 0;
        t0 = clock();
        p = run_case(&c, (uint32_t)(1000 + i), &res);
        if (getenv_verbose())
            printf("    chi2 %-16s lobe %d r=%-6g cos=%-6g: chi2=%8.2f dof=%3d p=%.4f rejected=%ld/%.1f pooled=%d "
                   "(%.2f s)\n",
                   type_name(specs[i].type), specs[i].lobe, (double)specs[i].roughness, (double)specs[i].cos_o,
                   res.chi2, res.dof, p, res.rejected, res.expected_rejected, res.pooled_cells,
                   (double)(clock() - t0) / CLOCKS_PER_SEC);
        fflush(stdout);
        if (res.pdf_integral > 1 + 1e-4) { /* a density cannot integrate above 1: quadrature failed */
            snprintf(why, why_size, "%s lobe %d r=%g cos=%g: pdf integrates to %.6f", type_name(specs[i].type),
                     specs[i].lobe, (double)specs[i].roughness, (double)specs[i].cos_o, res.pdf_integral);
            return 0;
        }
        if (!(p >= level)) {
            snprintf(why, why_size, "%s lobe %d r=%g cos=%g: chi2=%g dof=%d p=%g < %g", type_name(specs[i].type),
                     specs[i].lobe, (double)specs[i].roughness, (double)specs[i].cos_o, res.chi2, res.dof, p, level);
            return 0;
        }
    }
    return 1;
}

/* The representative subset: every non-delta lobe kind, roughness 0.1-1, normal
 * to grazing incidence, both sides of the rough dielectric; 10^6 samples each. */
TEST(chi2_bsdf_lobes)
{
    static const chi2_case_spec specs[] = {
        {MAT_LAMBERT, 0, 1, (real)0.7},
        {MAT_CONDUCTOR, 0, (real)0.5, (real)0.7},
        {MAT_CONDUCTOR, 0, (real)0.1, (real)0.01},
        {MAT_PLASTIC, 1, (real)0.5, (real)0.3},
        {MAT_ROUGH_DIELECTRIC, 0, (real)0.5, (real)0.7},
        {MAT_ROUGH_DIELECTRIC, 1, (real)0.5, (real)0.7},
        {MAT_ROUGH_DIELECTRIC, 1, (real)0.1, (real)-0.9},
    };
    char why[512];
    CHECKF(run_family(specs, (int)(sizeof specs / sizeof specs[0]), why, sizeof why), "%s", why);
}

/* Power: the same machinery must reject a pdf that is 5% too high on half the sphere. */
TEST(chi2_rejects_broken_pdf)
{
    lobe_case c;
    chi2_result res;
    double p;
    c.b = make_bsdf(MAT_CONDUCTOR, (real)0.5, (real)1.5);
    c.lobe = 0;
    c.wo = wo_at((real)0.7);
    c.broken = 1;
    p = run_case(&c, 999, &res);
    CHECKF(p >= 0 && p < 1e-6, "broken pdf not rejected: chi2=%g dof=%d p=%g", res.chi2, res.dof, p);
}

/* The full grid (make test-long): every non-delta lobe x roughness {1e-3 (double
 * build only), 0.1, 0.5, 1} x cos theta_o {1, 0.7, 0.3, 0.01}, dielectrics from
 * both sides. */
TEST_LONG(chi2_bsdf_lobes_grid)
{
    static const real roughness[] = {(real)1e-3, (real)0.1, (real)0.5, 1};
    static const real cosines[] = {1, (real)0.7, (real)0.3, (real)0.01};
    chi2_case_spec specs[128];
    int n = 0, r, a, side;
    char why[512];
    specs[n].type = MAT_LAMBERT, specs[n].lobe = 0, specs[n].roughness = 1, specs[n].cos_o = (real)0.5, ++n;
    for (r = 0; r < 4; ++r) {
        if (r == 0 && sizeof(real) < 8) continue; /* alpha = 1e-6 is below float direction resolution */
        for (a = 0; a < 4; ++a) {
            chi2_case_spec s;
            s.roughness = roughness[r];
            s.cos_o = cosines[a];
            s.type = MAT_CONDUCTOR, s.lobe = 0, specs[n++] = s;
            s.type = MAT_PLASTIC, s.lobe = 1, specs[n++] = s;
            for (side = 0; side < 2; ++side) {
                s.cos_o = side ? -cosines[a] : cosines[a];
                s.type = MAT_ROUGH_DIELECTRIC, s.lobe = 0, specs[n++] = s;
                s.type = MAT_ROUGH_DIELECTRIC, s.lobe = 1, specs[n++] = s;
            }
        }
    }
    CHECKF(run_family(specs, n, why, sizeof why), "%s", why);
}
