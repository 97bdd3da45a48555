/* restir_render as a whole: byte-identical for any thread count, reservoirs that pass
 * the path-sample invariants (and round-trip through the dump format), option rows of
 * `render --method restir`, validation, and `restir inspect`. */
#include <stdlib.h>
#include <math.h>
#include <string.h>
#include "../src/cli/render_restir.h"
#include "restir/core/json_text.h"
#include "restir/restir/reservoir_dump.h"
#include "restir/frame/offline.h"
#include "restir_util.h"
#include "test.h"
#include "restir/frame/frame_stats.h"
#include "restir/frame/options.h"

static int render(const scene *s, const restir_options *o, restir_result *r)
{
    rerror e;
    if (restir_render(s, o, r, &e)) {
        test_fail(__FILE__, __LINE__, "restir_render: %s", e.msg);
        return -1;
    }
    return 0;
}

/* Wall-clock fields differ between runs; everything else must not. */
static void clear_timings(restir_stats *st)
{
    st->ms_gbuffer = st->ms_initial = st->ms_shade = 0;
    memset(st->ms_spatial, 0, sizeof st->ms_spatial);
}

TEST(restir_render_deterministic_across_threads)
{
    scene s;
    restir_options o;
    restir_result a, b;
    int shift;
    if (rt_load_scene("scenes/cornell-glossy.scene", 24, &s)) return;
    for (shift = 0; shift < RESTIR_SHIFT_COUNT && !test_has_failed(); ++shift) {
        restir_options_default(&o);
        o.seed = test_seed();
        o.shift = shift;
        o.spatial_passes = 2;
        o.spatial.neighbors = 3;
        o.spatial.mis = shift == 0 ? MIS_PAIRWISE_DEFENSIVE : shift == 1 ? MIS_PAIRWISE_UNIFORM : MIS_TALBOT;
        o.spatial.pattern = shift == 2 ? NEIGHBOR_UNIFORM : NEIGHBOR_R2;
        o.frames = 2;
        o.candidates = 2;
        o.max_depth = 5;
        o.jitter = 1;
        o.russian_roulette = 1;
        o.threads = 1;
        if (render(&s, &o, &a)) break;
        o.threads = 3;
        if (render(&s, &o, &b)) {
            restir_result_free(&a);
            break;
        }
        CHECKF(memcmp(a.mean.px, b.mean.px, 3 * sizeof(float) * 24 * 24) == 0, "shift %s: images differ between 1 and 3 threads",
               restir_shift_names[shift]);
        clear_timings(&a.stats);
        clear_timings(&b.stats);
        CHECK(memcmp(&a.stats, &b.stats, sizeof a.stats) == 0);
        CHECK(a.stats.initial.record_failed == 0 && a.stats.initial.record_mismatch == 0);
        CHECK(a.stats.spatial.pixels > 0 && a.stats.spatial.outcome[SHIFT_OK] > 0 && a.stats.spatial.mis_shifts > 0);
        restir_result_free(&a);
        restir_result_free(&b);
    }
    scene_free(&s);
}

/* Every final reservoir (initial or resampled) passes path_sample_check, has confidence
 * N times the number of domains it resampled (1 + accepted neighbours, up to 6), and
 * survives the dump format. */
TEST(restir_render_reservoirs_are_valid_and_dumpable)
{
    scene s;
    restir_options o;
    restir_result r;
    rerror e;
    reservoir_dump_info info;
    reservoir *back = NULL;
    long p, n, valid = 0;
    const char *path = test_tmp_path("restir.bin");
    if (rt_load_scene("scenes/cornell.scene", 16, &s)) return;
    restir_options_default(&o);
    o.seed = test_seed();
    o.spatial_passes = 1;
    o.candidates = 3;
    o.keep_reservoirs = 1;
    if (render(&s, &o, &r)) return;
    n = (long)s.width * s.height;
    for (p = 0; p < n; ++p) {
        const reservoir *q = &r.reservoirs[p];
        CHECKF(path_sample_check(&q->y, "reservoir", &e) == 0, "pixel %ld: %s", p, e.msg);
        CHECKF(q->confidence == 0 || (q->confidence >= 3 && q->confidence <= 21 && fmod((double)q->confidence, 3) == 0),
               "pixel %ld: confidence %g", p, (double)q->confidence);
        valid += path_sample_is_valid(&q->y);
    }
    CHECK(valid > n / 2);
    memset(&info, 0, sizeof info);
    info.width = (uint32_t)s.width;
    info.height = (uint32_t)s.height;
    snprintf(info.tag, sizeof info.tag, "spatial1");
    CHECKF(reservoir_dump_write(path, r.reservoirs, &info, &e) == 0, "%s", e.msg);
    CHECKF(reservoir_dump_read(path, &back, &info, &e) == 0, "%s", e.msg);
    for (p = 0; p < n; ++p) CHECK(back[p].W == r.reservoirs[p].W && back[p].y.rc_k == r.reservoirs[p].y.rc_k);
    free(back);
    restir_result_free(&r);
    scene_free(&s);
}

TEST(restir_options_rows_and_validation)
{
    restir_options o, d;
    render_restir_flags f;
    cli_option rows[RENDER_RESTIR_OPTION_ROWS + 1];
    const char *positional[1];
    char *argv[] = {"render",      "--shift",       "reconnection", "--spatial-passes", "1",     "--frames", "7",
                    "--candidates", "4",            "--paths",      "indirect",         "--ablate", "light-pdf",
                    "--distance-threshold", "0.05", "scene.scene", NULL};
    int n, count, argc = (int)(sizeof argv / sizeof argv[0]) - 1;
    rerror e;
    restir_options_default(&o);
    n = render_restir_options(rows, &o, &f);
    CHECK(n > 10 && n <= RENDER_RESTIR_OPTION_ROWS);
    memset(&rows[n], 0, sizeof rows[n]);
    CHECK(cli_parse("render", argc, argv, rows, positional, 1, &count) == 0 && count == 1);
    CHECK(o.shift == RESTIR_SHIFT_RECONNECTION && o.spatial_passes == 1 && o.frames == 7 && o.candidates == 4);
    CHECK(o.paths == RESTIR_PATHS_INDIRECT && o.ablation == RESTIR_ABLATE_LIGHT_PDF && o.distance_threshold == 0.05);
    CHECKF(restir_options_validate(&o, &e) == 0, "%s", e.msg);
    restir_options_default(&d);
    CHECK(d.shift == RESTIR_SHIFT_HYBRID && d.spatial_passes == 0 && d.spatial.mis == MIS_TALBOT && d.candidates == 1);
    CHECK(d.roughness_threshold == 0.2 && d.distance_threshold == 0.02);
    o = d; o.spatial_passes = RESTIR_MAX_SPATIAL_PASSES + 1; CHECK(restir_options_validate(&o, &e) != 0);
    o = d; o.spatial.neighbors = 0; CHECK(restir_options_validate(&o, &e) != 0);
    o = d; o.spatial.mis = MIS_FAMILY_COUNT; CHECK(restir_options_validate(&o, &e) != 0);
    o = d; o.spatial.algorithm = SPATIAL_STOCHASTIC_PAIRWISE; CHECK(restir_options_validate(&o, &e) == 0);
    o = d; o.spatial.algorithm = (enum spatial_algorithm)2; CHECK(restir_options_validate(&o, &e) != 0);
    o = d; o.stochastic.n_picks = 0; CHECK(restir_options_validate(&o, &e) != 0);
    o = d; o.stochastic.n_canonical_picks = STOCHASTIC_MAX_PICKS + 1; CHECK(restir_options_validate(&o, &e) != 0);
    o = d; o.temporal.mis = MIS_FAMILY_COUNT; CHECK(restir_options_validate(&o, &e) != 0);
    o = d; o.time_limit = -1; CHECK(restir_options_validate(&o, &e) != 0);
    o = d; o.spatial.pattern = NEIGHBOR_BOX; o.spatial.radius = 16; CHECK(restir_options_validate(&o, &e) != 0);
    o = d; o.spatial.pattern = NEIGHBOR_BOX; o.spatial.radius = 3; CHECK(restir_options_validate(&o, &e) == 0);
    o = d; o.max_depth = 17; CHECK(restir_options_validate(&o, &e) != 0);
    o = d; o.paths = RESTIR_PATHS_INDIRECT; o.max_depth = 2; CHECK(restir_options_validate(&o, &e) != 0);
    o = d; o.candidates = 0; CHECK(restir_options_validate(&o, &e) != 0);
    o = d; o.frames = 0; CHECK(restir_options_validate(&o, &e) != 0);
}

TEST(restir_inspect_cli)
{
    char out[8192];
    int status = test_cli(out, sizeof out, "inspect scenes/cornell.scene --size 32x32 --pixel 10,20 --neighbor 12,19");
    CHECKF(status == 0, "exit %d: %s", status, out);
    CHECKF(strstr(out, "pixel (10, 20)") && strstr(out, "shift to pixel (12, 19)"), "%s", out);
    status = test_cli(out, sizeof out, "inspect scenes/cornell.scene --pixel 10");
    CHECKF(status == 2, "exit %d: %s", status, out);
    status = test_cli(out, sizeof out, "inspect scenes/cornell.scene --size 32x32 --pixel 40,1");
    CHECKF(status == 2 && strstr(out, "outside"), "exit %d: %s", status, out);
}

/* The --stats counters are well-formed JSON (restir_stats_write_json) with every failure
 * reason as a key. */
TEST(restir_stats_json_well_formed)
{
    scene s;
    restir_options o;
    restir_result r;
    rerror e;
    json_reader jr;
    const char *path = test_tmp_path("restir-stats.json");
    FILE *f;
    if (rt_load_scene("scenes/cornell.scene", 8, &s)) return;
    restir_options_default(&o);
    o.spatial_passes = 1;
    if (render(&s, &o, &r)) return;
    f = fopen(path, "w");
    CHECK(f != NULL);
    restir_stats_write_json(f, &r.stats, "");
    fputc('\n', f);
    fclose(f);
    CHECKF(json_reader_open(&jr, path, &e) == 0, "%s", e.msg);
    CHECKF(json_skip_value(&jr) == 0 && json_expect_end(&jr) == 0, "%s", e.msg);
    CHECK(strstr(jr.text, "\"rc_prev\"") && strstr(jr.text, "\"shift_outcomes\"") && strstr(jr.text, "\"nonfinite\""));
    json_reader_close(&jr);
    restir_result_free(&r);
    scene_free(&s);
}

/* Issue 25: each technique validates its own options and says so in its own terms (no
 * CLI flag in a library message); stochastic pairwise MIS is a spatial algorithm, chosen
 * by --mis stochastic-pairwise without touching the MIS family, and a preset's family
 * survives it. */
TEST(restir_options_techniques_validate_their_own)
{
    static const struct {
        const char *argv, *prefix;
    } cases[] = {
        {"mutation count -3", "mutation: count -3"},   {"spatial algorithm 7", "spatial: "},
        {"temporal mcap 0", "temporal: "},              {"stochastic picks 0", "stochastic: "},
        {"correlation boiling 2", "correlation: "},     {"light tiles alone", "light RIS: "},
        {"dedup with infinite cap", "restir: "},        {"vector shading, stochastic", "restir: "},
    };
    restir_options d, o;
    rerror e;
    int i;
    restir_options_default(&d);
    for (i = 0; i < (int)(sizeof cases / sizeof *cases); ++i) {
        o = d;
        switch (i) {
        case 0: o.mutation.count = -3; break;
        case 1: o.spatial.algorithm = (enum spatial_algorithm)7; break;
        case 2: o.temporal.mcap = 0; break;
        case 3: o.stochastic.n_picks = 0; break;
        case 4: o.correlation.boiling_filter = 2; break;
        case 5: o.light_ris.tiles = 1; break;
        case 6: o.correlation.dedup = 1; o.temporal.mcap = INFINITY; break;
        default: o.shading = RESTIR_SHADING_VECTOR; o.spatial.algorithm = SPATIAL_STOCHASTIC_PAIRWISE; break;
        }
        e.msg[0] = '\0';
        CHECKF(restir_options_validate(&o, &e) != 0, "%s: accepted", cases[i].argv);
        CHECKF(!strncmp(e.msg, cases[i].prefix, strlen(cases[i].prefix)), "%s: '%s' (want '%s...')", cases[i].argv,
               e.msg, cases[i].prefix);
        CHECKF(!strstr(e.msg, "--"), "%s: a library message names a CLI flag: '%s'", cases[i].argv, e.msg);
    }
}

/* --mis stochastic-pairwise and --preset, in both orders, through the CLI's mapping. */
static void parse_restir_args(const char *args, restir_options *o)
{
    cli_option rows[RENDER_RESTIR_OPTION_ROWS + 2];
    int given[RENDER_RESTIR_OPTION_ROWS + 2], n, count, preset = 0, argc = 0;
    render_restir_flags f;
    char buf[256], *argv[16], *t;
    const char *positional[1];
    snprintf(buf, sizeof buf, "render %s", args);
    for (t = strtok(buf, " "); t && argc < 15; t = strtok(NULL, " ")) argv[argc++] = t;
    argv[argc] = NULL;
    restir_options_default(o);
    rows[0] = render_restir_preset_row(&preset);
    n = 1 + render_restir_options(rows + 1, o, &f);
    memset(&rows[n], 0, sizeof rows[n]);
    cli_track_given(rows, given);
    CHECKF(cli_parse("render", argc, argv, rows, positional, 1, &count) == 0, "%s", args);
    render_restir_apply(rows, given, preset, &f, o);
}

TEST(restir_cli_mis_stochastic_is_an_algorithm)
{
    restir_options o;
    parse_restir_args("--mis stochastic-pairwise", &o);
    CHECK(o.spatial.algorithm == SPATIAL_STOCHASTIC_PAIRWISE && o.spatial.mis == MIS_TALBOT);
    CHECK(!strcmp(spatial_mis_name(&o.spatial), "stochastic-pairwise"));
    parse_restir_args("--preset gris-offline --mis stochastic-pairwise", &o);
    CHECK(o.spatial.algorithm == SPATIAL_STOCHASTIC_PAIRWISE && o.candidates == 32);
    parse_restir_args("--mis stochastic-pairwise --preset gris-offline --no-confidence-scaling", &o);
    CHECK(o.spatial.algorithm == SPATIAL_STOCHASTIC_PAIRWISE && !o.stochastic.confidence_scaling);
    parse_restir_args("--preset gris-offline", &o);
    CHECK(o.spatial.algorithm == SPATIAL_GRIS_STEP && o.spatial.mis == MIS_PAIRWISE_DEFENSIVE);
    CHECK(o.stochastic.confidence_scaling);
    parse_restir_args("--mis talbot --preset gris-realtime", &o);
    CHECK(o.spatial.algorithm == SPATIAL_GRIS_STEP && o.spatial.mis == MIS_TALBOT && o.spatial.radius == 20);
    CHECK(!strcmp(spatial_mis_name(&o.spatial), "talbot"));
}
