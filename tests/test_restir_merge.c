/* Two-domain resampling (one spatial pass, one neighbour; gris_resample): every pixel merged with one random
 * neighbour, averaged over frames, is an unbiased estimator of the path tracer's image
 * for every shift (K-run statistics of `restir check`), and the same comparison rejects
 * the deliberately broken variants --ablate jacobian and --ablate light-pdf.
 *
 * Where the ablations show. Both bias a pixel towards what its NEIGHBOURS see, so they
 * act like a blur of part of the image: the image mean barely moves (pixel pairs (c, n)
 * and (n, c) cancel to first order) and the per-block tests must be local (4 x 4
 * blocks). Dropping |dT/dx| biases pixel c by about E[J_{c->n}] - 1, the ratio of the
 * neighbour's to its own incident (reconnectable) radiance minus one: large where
 * indirect light changes fast, e.g. at the foot of a lit wall. A stale light pdf biases
 * direct light by p_light(y_{d-1}) / p_light(x_{d-1}), large next to a small light
 * close to a surface. The "spot" scene has both. */
#include <stdlib.h>
#include <string.h>
#include "pt_util.h"
#include "restir_util.h"
#include "test.h"
#include "restir/frame/options.h"

#define ALPHA 1e-3
static int runs = 16; /* K runs per side (the TEST_LONG versions use more) */


typedef struct {
    int shift, ablation, paths, max_depth, frames, block;
    uint32_t pt_spp;
    double radius;
    uint32_t salt; /* per scene: the scenes' comparisons use independent seeds */
} merge_case;

/* FNV-1a of the scene path. Without it cornell and cornell-glossy (nearly the same
 * geometry) ran on the same seeds, so one unlucky seed failed both (seed 9: hybrid
 * indirect, mean z -3.6 and -4.3; at 512 runs the same cases agree with the path tracer
 * to -0.09% +- 0.08%, docs/statistics.md, "Followed up (session 9)"). */
static uint32_t scene_salt(const char *path)
{
    uint32_t h = 2166136261u;
    for (; *path; ++path) h = (h ^ (unsigned char)*path) * 16777619u;
    return h;
}

static void report(const char *what, const check_result *c)
{
    if (getenv("RESTIR_TEST_VERBOSE"))
        fprintf(stderr, "  %s: mean z %.2f (lum %.6g vs %.6g), %ld/%ld blocks rejected, worst block z %.2f\n", what,
                rt_mean_z(c), c->lum_a.mean, c->lum_b.mean, c->rejected, c->tests, c->worst.z);
}

/* The path tracer's side of the comparisons of one scene and case (K = 16 runs). */
static int reference(const scene *s, const merge_case *m, check_side *pt)
{
    return rt_pt_side(s, test_seed() * 7919u + 3 + m->salt, runs, m->pt_spp, m->max_depth, m->paths == RESTIR_PATHS_INDIRECT,
                      m->block, pt);
}

/* restir with one spatial pass (K = 16 runs of `frames` frames) against the reference. */
static void expect(const scene *s, const char *name, const merge_case *m, const check_side *pt, int biased)
{
    restir_options o;
    check_side a;
    check_result c;
    check_options opt;
    rerror e;
    char what[256];
    int status;
    restir_options_default(&o);
    o.seed = test_seed() * 613u + 7u * (uint32_t)m->shift + 1 + m->salt;
    o.shift = m->shift;
    o.ablation = m->ablation;
    o.paths = m->paths;
    o.spatial_passes = 1;
    o.spatial.neighbors = 1;
    o.spatial.radius = m->radius;
    o.frames = m->frames;
    o.max_depth = m->max_depth;
    o.threads = 2;
    if (rt_restir_side(s, &o, runs, m->block, &a)) return;
    check_options_default(&opt);
    opt.alpha = ALPHA;
    opt.block_size = m->block;
    status = check_compare(&a, pt, &opt, &c, &e);
    check_side_free(&a);
    CHECKF(status == 0, "check_compare: %s", e.msg);
    snprintf(what, sizeof what, "%s %s paths %s ablate %s", name, restir_shift_names[m->shift],
             restir_paths_names[m->paths], restir_ablation_names[m->ablation]);
    report(what, &c);
    check_result_free(&c);
    if (biased)
        CHECKF(c.different, "%s: the broken estimator was not detected (mean z %.2f, worst block z %.2f)", what,
               rt_mean_z(&c), c.worst.z);
    else
        CHECKF(!c.different,
               "%s: merged image differs from the path tracer: mean z %.2f (p %.3g), %ld of %ld blocks rejected, worst "
               "z %.2f",
               what, rt_mean_z(&c), c.global.p, c.rejected, c.tests, c.worst.z);
}

static void every_shift_case(const scene *s, const char *path, merge_case m)
{
    check_side pt;
    if (reference(s, &m, &pt)) return;
    for (m.shift = 0; m.shift < RESTIR_SHIFT_COUNT && !test_has_failed(); ++m.shift) expect(s, path, &m, &pt, 0);
    check_side_free(&pt);
}

/* All paths and indirect paths alone (GRIS's figures measure indirect light). */
static void every_shift_at(const char *path, int res, int scale, int frames_factor)
{
    scene s;
    merge_case all = {0, RESTIR_ABLATE_NONE, RESTIR_PATHS_ALL, 4, 4, 8, 64, 6, 0};
    /* Indirect light through the glossy boxes is heavy-tailed: with 8 frames per run the
     * Welch test on 16 runs rejected a correct hybrid shift for 2 of 40 seeds (always with
     * z < 0, the skewness signature; the 32x larger TEST_LONG version shows mean z -0.45 +-
     * 0.37 over 9 seeds). 16 frames per run: 0 of 40. */
    merge_case indirect = {0, RESTIR_ABLATE_NONE, RESTIR_PATHS_INDIRECT, 4, 16, 8, 128, 6, 0};
    all.frames *= scale * frames_factor;
    indirect.frames *= scale * frames_factor;
    all.max_depth = indirect.max_depth = scale > 1 ? 6 : 4;
    all.radius = indirect.radius = 6.0 * res / 16;
    all.salt = indirect.salt = scene_salt(path);
    if (rt_load_scene(path, res, &s)) return;
    every_shift_case(&s, path, all);
    if (!test_has_failed()) every_shift_case(&s, path, indirect);
    scene_free(&s);
}

TEST(restir_merge_unbiased_every_shift_cornell) { every_shift_at("scenes/cornell.scene", 16, 1, 1); }

/* Twice the frames: the glossy boxes make the per-run block means right-skewed (image
 * mean skewness 0.8 at 16 frames, hybrid, indirect), and with the frames of the diffuse
 * box the block tests rejected a correct shift at block z -4.2 and -4.4 for 2 of the first
 * 23 salted seeds (2 and 22), always on the dark side, the skewness signature. */
TEST(restir_merge_unbiased_every_shift_cornell_glossy) { every_shift_at("scenes/cornell-glossy.scene", 16, 1, 2); }

/* 32 x 32, paths up to d = 6, 32 runs of 16 (all) or 32 (indirect) frames. */
TEST_LONG(restir_merge_unbiased_every_shift_long)
{
    runs = 32;
    every_shift_at("scenes/cornell.scene", 32, 4, 1);
    if (!test_has_failed()) every_shift_at("scenes/cornell-glossy.scene", 32, 4, 1);
    runs = 16;
}

/* The spot scene: every shift unbiased, and both ablations rejected by the very same
 * comparison (4 x 4 blocks: the biases are local). */
static void spot_case(int res, int scale)
{
    scene s;
    check_side pt;
    merge_case m = {0, RESTIR_ABLATE_NONE, RESTIR_PATHS_ALL, 3, 16, 4, 256, 4, 0};
    m.frames *= scale;
    m.radius = 4.0 * res / 16;
    if (rt_make_spot(&s, res) || test_scene_prepare(&s)) return;
    if (reference(&s, &m, &pt)) return;
    for (m.shift = 0; m.shift < RESTIR_SHIFT_COUNT && !test_has_failed(); ++m.shift) expect(&s, "spot", &m, &pt, 0);
    for (m.shift = RESTIR_SHIFT_RECONNECTION; m.shift <= RESTIR_SHIFT_HYBRID && !test_has_failed(); m.shift += 2) {
        m.ablation = RESTIR_ABLATE_JACOBIAN;
        expect(&s, "spot", &m, &pt, 1);
        m.ablation = RESTIR_ABLATE_LIGHT_PDF;
        if (!test_has_failed()) expect(&s, "spot", &m, &pt, 1);
        m.ablation = RESTIR_ABLATE_NONE;
    }
    check_side_free(&pt);
    scene_free(&s);
}

TEST(restir_merge_spot_unbiased_and_ablations_rejected) { spot_case(16, 1); }

/* 32 x 32, 32 runs of 32 frames. */
TEST_LONG(restir_merge_spot_long)
{
    runs = 32;
    spot_case(32, 2);
    runs = 16;
}
