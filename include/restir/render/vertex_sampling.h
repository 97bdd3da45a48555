/* The per-vertex steps of unidirectional path sampling, shared by the reference path
 * tracer (render/pt) and ReSTIR's initial sampling, replay and reconnection (docs/design.md, Layout).
 *
 * Vertex indexing follows GRIS §7.1: x0 is the camera, x1 the primary hit, ...; a path
 * (x0, ..., x_d) has length d = number of segments; d = 2 is direct lighting.
 * At each surface vertex x_i (i >= 1) three independent steps may run:
 *   - next-event estimation (NEE): sample a point y on a light; the path
 *     (x0..x_i, y) has length i+1 and ends with the NEE technique;
 *   - BSDF sampling with ONE lobe per bounce (GRIS §7.6): pick lobe l with P(l|wo),
 *     then wi from that lobe; the throughput factor is f_l|cos|/(P(l) pdf_l);
 *   - if the BSDF-sampled ray hits an emitter at x_{i+1}, the path of length i+1
 *     ends with the BSDF technique.
 * The two techniques are combined with the balance heuristic of GRIS Eq. 49, where
 * the BSDF pdf is the ALL-LOBE pdf sum_l P(l|wo) pdf_l(wi) (GRIS §7.6: "p_1 and p_2
 * are the NEE and BSDF sampling PDFs of the path, and sum over all BSDF lobes").
 *
 * Random numbers (docs/rng.md): the BSDF step at vertex i uses stream RNG_BSDF,
 * vertex i, slots 0 (lobe), 1, 2 (direction); NEE at vertex i uses RNG_NEE, vertex i,
 * slots 0 (light column), 1 (alias coin), 2, 3 (point on the triangle). */
#ifndef RESTIR_PATH_SAMPLER_H
#define RESTIR_PATH_SAMPLER_H

#include "restir/scene/bsdf.h"
#include "restir/scene/lights.h"
#include "restir/core/rng.h"
#include "restir/scene/scene.h"

/* Deliberately broken variants (`--ablate NAME`): each must make the estimator-equality
 * tests fail. They are teaching material: what a plausible bug does to the image. */
enum pt_ablation {
    PT_ABLATE_NONE = 0,
    PT_ABLATE_LIGHT_PDF = 1u << 0, /* "light-pdf": the light pdf is 5% too large everywhere */
    PT_ABLATE_MIS_SUM = 1u << 1,   /* "mis-sum": NEE uses the balance heuristic, BSDF hits the
                                      power heuristic; the weights no longer sum to one */
    PT_ABLATE_MIS_LOBE = 1u << 2,  /* "mis-lobe": the BSDF hit's MIS weight uses the pdf of the
                                      sampled lobe P(l) pdf_l instead of the all-lobe pdf
                                      (contradicts GRIS §7.6); biased on multi-lobe materials */
    PT_ABLATE_LIGHT_RIS_PDF = 1u << 3 /* "light-ris-pdf": with light RIS, the BSDF hit's MIS weight
                                      uses the base light pdf p_0 while NEE uses p̃ = 1/W: the
                                      weights no longer sum to one (docs/enhanced.md §6) */
};

/* Which techniques contribute (each alone is an unbiased estimator of the same image). */
enum pt_strategy {
    PT_STRATEGY_MIS = 0,  /* NEE + BSDF sampling, balance heuristic (GRIS Eq. 49) */
    PT_STRATEGY_NEE = 1,  /* NEE only; emitters hit after delta bounces (and at x1) still count */
    PT_STRATEGY_BSDF = 2  /* BSDF sampling only: every emitter hit counts with weight 1 */
};

typedef struct {
    const scene *scene;
    const light_set *lights;
    enum pt_strategy strategy;
    unsigned ablations; /* enum pt_ablation bits */
    int light_ris;      /* N: NEE by light RIS with N candidates at x1 (light_ris.h); 0 = plain p_0 */
    int light_tiles;    /* 1: light RIS candidates come from light tiles (light_ris.h) */
    int image_width;    /* pixels per image row: a path's 8×8 screen tile (light tiles only) */
} path_context;

/* One surface vertex x_i, prepared for shading. */
typedef struct {
    surface_hit hit;
    vec3 position;       /* hit.position in real precision */
    vec3 ng, ns;         /* geometric and shading normal (unit) */
    vec3 wo;             /* unit direction towards x_{i-1} */
    shading_frame frame; /* z = ns */
    vec3 wo_local;
    bsdf b;
    real lobe_p[BSDF_MAX_LOBES]; /* P(l|wo), bsdf_lobe_probabilities(&b, wo_local) */
    int can_nee;         /* 1 if some lobe with P(l|wo) > 0 is not a Dirac */
} path_vertex;

/* Builds vertex x_i from the hit of the ray that arrived along direction ray_dir. A vertex
 * built by hand must fill lobe_p too (the functions below read it instead of recomputing). */
void path_vertex_make(path_vertex *v, const scene *s, const surface_hit *h, vec3 ray_dir);

/* The vertex at infinity reached along the unit direction w (docs/environment.md):
 * hit.triangle = LIGHT_TRIANGLE_DISTANT, hit.position = position = w (as float, then
 * renormalised: light_distant_direction), ng = ns = wo = -w, a black BSDF, no NEE. */
void path_vertex_make_distant(path_vertex *v, vec3 w);
/* The same from the stored float direction p (bit for bit the vertex whose hit.position is p). */
void path_vertex_make_distant_stored(path_vertex *v, vec3f p);
static inline int path_vertex_is_distant(const path_vertex *v) { return v->hit.triangle == LIGHT_TRIANGLE_DISTANT; }
/* The direction of a vertex at infinity from its stored float position. */
static inline vec3 light_distant_direction(vec3f p) { return v3_normalize(v3_from_f(p)); }

/* Radiance leaving x_i towards x_{i-1}: Ke if x_i lies on the front face of a light,
 * 0 otherwise (one-sided emitters, docs/design.md, Conventions). */
rgb path_vertex_emitted(const path_context *c, const path_vertex *v);

/* All-lobe f(wo,wi)|cos| (non-delta lobes) and all-lobe pdf sum_l P(l|wo) pdf_l(wi)
 * (GRIS Eq. 49) for a world direction wi. Both are 0 where the shading frame and the
 * geometric normal disagree on the side of wi (no light leaks through shading normals);
 * the same rule applies to sampled directions, so all strategies share one f. */
rgb path_vertex_eval(const path_vertex *v, vec3 wi);
real path_vertex_pdf(const path_vertex *v, vec3 wi);
/* Both of the above in one pass (one frame transform; bsdf_eval_pdf_given), bit for bit. */
void path_vertex_eval_pdf(const path_vertex *v, vec3 wi, rgb *f_cos, real *pdf);
/* One lobe (GRIS §7.6, a BSDF-sampled vertex evaluates only its lobe): f_l|cos| and the
 * pdf of sampling wi through this lobe INCLUDING the lobe selection, P(l|wo) pdf_l(wi),
 * with the side rule of path_vertex_eval. Returns 1 if both are nonzero; 0 (and zeros)
 * for a Dirac lobe, a lobe index the material lacks, P(l|wo) = 0, or f = 0. */
int path_vertex_eval_lobe(const path_vertex *v, int lobe, vec3 wi, rgb *f_cos, real *pdf);

/* The light pdf used by the estimator: light_pdf_solid_angle, times 1.05 under the
 * light-pdf ablation. Solid angle at x; y on triangle tri with normal ny. */
real path_light_pdf(const path_context *c, uint32_t tri, vec3 x, vec3 y, vec3 ny);

/* ---- NEE at one vertex ---- */
typedef struct {
    light_sample y;
    vec3 wi;           /* unit direction x_i -> y */
    rgb f_cos;         /* all-lobe f|cos| at x_i towards y */
    rgb emitted;       /* Ke of y towards x_i (0 from behind) */
    real pdf_light;    /* solid angle at x_i */
    real pdf_bsdf;     /* all-lobe BSDF pdf of wi (GRIS Eq. 49) */
    rgb contribution;  /* f_cos · emitted / pdf_light, before the MIS weight (0 if occluded) */
    int shadow_ray;    /* 1 if a shadow ray was traced */
} nee_sample;

/* Samples a light point for vertex x_i (vertex_index = i) and tests visibility. Returns 1
 * if the contribution is nonzero, 0 otherwise (no light, occluded, back side, f = 0).
 * With c->light_ris > 0 this is light RIS (light_ris.h): pdf_light is then p̃ = 1/W.
 * `path` is the path's base key. It and vertex_sample_bsdf's are passed by address: a
 * 24-byte key passed by value is copied to the stack on every call of the hot loop, and
 * reading that copy back stalled the path tracer (docs/performance.md, round 2: 1.09x). */
int vertex_sample_light(const path_context *c, const path_vertex *v, const rng_key *path, uint32_t vertex_index,
                        nee_sample *out);
/* The same from explicit numbers u[0..1] (light selection), u[2..3] (point on the light):
 * replay of MCMC-mutated NEE numbers (Mutations §4.2). */
int vertex_sample_light_numbers(const path_context *c, const path_vertex *v, const real u[4], nee_sample *out);

/* ---- BSDF sampling at one vertex (one lobe per bounce, GRIS §7.6) ---- */
typedef struct {
    vec3 wi;           /* world direction */
    int lobe, is_delta;
    rgb weight;        /* f_l|cos| / (P(l|wo) pdf_l): the throughput factor */
    real pdf_lobe;     /* P(l|wo) pdf_l(wi) (1·P(l) for a Dirac) */
    real pdf_all;      /* all-lobe pdf of wi (0 for a Dirac: NEE cannot produce it) */
} bsdf_bounce;

/* The BSDF step from explicit numbers (u_lobe picks the lobe, u the direction): random
 * replay and primary-sample-space mutations supply their own numbers. Returns 1 and fills
 * *out, or 0 if the BSDF produced no valid direction. */
int vertex_sample_bsdf_numbers(const path_vertex *v, real u_lobe, vec2 u, bsdf_bounce *out);
/* The same step with the RNG_BSDF numbers of the path, for the path tracer, which needs the
 * all-lobe pdf only when the bounce reaches an emitter: out->pdf_all is left at -1 and *s
 * keeps the lobe's sample, from which path_bounce_pdf_all computes it then (for a two-lobe
 * material that is the other lobe's pdf saved at every other bounce; docs/performance.md,
 * round 2). With pdf_all filled in so, bit for bit vertex_sample_bsdf_numbers's result. */
int vertex_sample_bsdf(const path_vertex *v, const rng_key *path, uint32_t vertex_index, bsdf_bounce *out,
                       bsdf_sample_record *s);
/* bsdf_bounce.pdf_all of the sample s drawn at v (GRIS §7.6: summed over all lobes). */
real path_bounce_pdf_all(const path_vertex *v, const bsdf_sample_record *s);

/* ---- MIS (GRIS Eq. 49, balance heuristic) ---- */
/* p_this / (p_this + p_other); 0 if both are 0. */
real path_mis_balance(real p_this, real p_other);
/* Weight of an NEE sample with light pdf p_light and all-lobe BSDF pdf p_bsdf. */
real path_mis_weight_nee(const path_context *c, real p_light, real p_bsdf);
/* The NEE pdf of the emitter point `hit` reached by BSDF sampling from x_i = `from`
 * (vertex_index = i, path = the path's base key), for its MIS weight: path_light_pdf, or
 * with light RIS the estimate p̃ of light_ris_pdf_hit (p_0 under the light-ris-pdf ablation). */
real path_light_pdf_hit(const path_context *c, const path_vertex *from, const path_vertex *hit, rng_key path,
                        uint32_t vertex_index);
/* Weight of a BSDF-sampled emitter hit after bounce b, whose light pdf is p_light. */
real path_mis_weight_bsdf_hit(const path_context *c, const bsdf_bounce *b, real p_light);

#endif
