/* The ReSTIR PT run configuration (include/restir/frame/options.h): defaults, the GRIS
 * §8.3 presets, validation, and what each estimator module is handed of it. */
#include "restir/frame/options.h"

#include <math.h>
#include <string.h>
#include "restir/render/light_ris.h"
#include "restir/restir/connectability.h"

const char *const restir_paths_names[] = {"all", "indirect", NULL};
const char *const restir_pairing_names[] = {"disk", "paired", NULL};
const char *const restir_motion_vector_names[] = {"single", "dual", NULL};
const char *const restir_shading_names[] = {"scalar", "vector", NULL};

void restir_options_default(restir_options *o)
{
    memset(o, 0, sizeof *o);
    o->shift = RESTIR_SHIFT_HYBRID;
    o->spatial_passes = 0;
    o->neighbors = 6;
    o->radius = 10;
    o->pattern = NEIGHBOR_R2;
    o->normal_cos = NEIGHBOR_DEFAULT_MIN_NORMAL_COS;
    o->depth_ratio = NEIGHBOR_DEFAULT_MAX_RELATIVE_DEPTH;
    o->mis = MIS_TALBOT;
    o->frames = 1;
    o->candidates = 1;
    o->max_depth = 10;
    o->roughness_threshold = 0.2;
    o->distance_threshold = 0.02;
    o->rc_criterion = RC_MODE_GRIS;
    o->footprint_c = 0.02;
    o->paths = RESTIR_PATHS_ALL;
    o->rr_min_depth = 3;
    o->seed = 1;
    o->threads = 1;
    o->quiet = 1;
    o->temporal = 1;
    o->temporal_mis = MIS_TALBOT;
    o->mcap = 20;
    o->stochastic_n = 1;
    o->stochastic_nc = 1;
    o->dedup_min = 1;    /* Enhanced §5: c_cap_min = 1, alpha = 0.1 */
    o->dedup_alpha = 0.1;
    o->mutate_after = MUTATE_AFTER_TEMPORAL;
}

void restir_neighbor_options_for(neighbor_options *no, const restir_options *o)
{
    neighbor_options_default(no);
    no->pattern = (enum neighbor_pattern)o->pattern;
    no->count = o->neighbors;
    no->radius = o->radius;
    no->reject_geometry = !o->no_reject;
    no->min_normal_cos = (float)o->normal_cos;
    no->max_relative_depth = (float)o->depth_ratio;
    if (o->pairing == RESTIR_PAIRING_PAIRED) no->pattern = NEIGHBOR_PAIRED;
}

int restir_pairing_build(neighbor_options *no, const restir_options *o, reuse_texture *textures, rerror *e)
{
    no->textures = NULL;
    if (no->pattern != NEIGHBOR_PAIRED) return 0;
    if (reuse_textures_build(textures, no->count, pairing_sigma_for_radius(o->radius), o->seed, e)) return -1;
    no->textures = textures;
    return 0;
}

int restir_pair_step_active(const restir_options *o)
{
    return o->pairing == RESTIR_PAIRING_PAIRED && !o->no_pair_step && o->mis != RESTIR_MIS_STOCHASTIC_PAIRWISE &&
           !o->cells && o->spatial_passes > 0;
}

void restir_pairing_free(neighbor_options *no)
{
    if (no->textures) reuse_textures_free((reuse_texture *)no->textures, no->count);
    no->textures = NULL;
}

/* GRIS §8.3: "we use defensive pairwise MIS for spatial reuse" (issue 9: the preset kept
 * Talbot before). */
void restir_options_preset_gris_offline(restir_options *o)
{
    o->candidates = 32;
    o->mis = MIS_PAIRWISE_DEFENSIVE;
    o->spatial_passes = 3;
    o->neighbors = 6;
    o->radius = 10;
    o->mis = MIS_PAIRWISE_DEFENSIVE;
}

void restir_options_preset_gris_realtime(restir_options *o)
{
    o->candidates = 1;
    o->temporal = 1;
    o->temporal_mis = MIS_TALBOT;
    o->mcap = 20;
    o->spatial_passes = 1;
    o->neighbors = 3;
    o->radius = 20;
    o->mis = MIS_PAIRWISE_DEFENSIVE;
}

int restir_options_biased(const restir_options *o) { return o->dedup || o->boiling_filter > 0; }

const char *const restir_pairwise_confidence_names[] = {"stochastic", "falcor", NULL};

mis_family restir_step_mis(const restir_options *o, int mis)
{
    if (mis == MIS_PAIRWISE_DEFENSIVE && o->pairwise_confidence == 1) return MIS_PAIRWISE_DEFENSIVE_FALCOR;
    return (mis_family)mis;
}

/* Issue 12 (docs/correlation.md): --dedup, --motion-vectors, --boiling-filter. */
static int correlation_options_validate(const restir_options *o, rerror *e)
{
    if (o->dedup && (isinf(o->mcap) || !(o->dedup_min > 0) || isinf(o->dedup_min)))
        return rerror_set(e, "restir: --dedup needs a finite --mcap and c_cap_min > 0 (got mcap %g, min %g)", o->mcap,
                          o->dedup_min);
    if (o->dedup && (!(o->dedup_alpha > 0) || isinf(o->dedup_alpha)))
        return rerror_set(e, "restir: --dedup-alpha %g (must be finite and > 0)", o->dedup_alpha);
    if (o->motion_vectors != RESTIR_MV_SINGLE && o->motion_vectors != RESTIR_MV_DUAL)
        return rerror_set(e, "restir: unknown motion vectors %d", o->motion_vectors);
    if (!(o->boiling_filter >= 0 && o->boiling_filter <= 1))
        return rerror_set(e, "restir: --boiling-filter %g (strength in (0, 1], 0 = off)", o->boiling_filter);
    return 0;
}

int restir_options_validate(const restir_options *o, rerror *e)
{
    int min_depth = o->paths == RESTIR_PATHS_INDIRECT ? 3 : 2;
    if (o->shift < 0 || o->shift >= RESTIR_SHIFT_COUNT) return rerror_set(e, "restir: unknown shift %d", o->shift);
    neighbor_options no;
    if (o->spatial_passes < 0 || o->spatial_passes > RESTIR_MAX_SPATIAL_PASSES)
        return rerror_set(e, "restir: %d spatial passes (0..%d)", o->spatial_passes, RESTIR_MAX_SPATIAL_PASSES);
    if (o->mis < 0 || o->mis > RESTIR_MIS_STOCHASTIC_PAIRWISE) return rerror_set(e, "restir: unknown MIS family %d", o->mis);
    if (o->stochastic_n < 1 || o->stochastic_n > STOCHASTIC_MAX_PICKS || o->stochastic_nc < 1 ||
        o->stochastic_nc > STOCHASTIC_MAX_PICKS)
        return rerror_set(e, "restir: --stochastic-n %d / --stochastic-nc %d outside 1..%d", o->stochastic_n,
                          o->stochastic_nc, STOCHASTIC_MAX_PICKS);
    if (!(o->radius >= 1) || !(o->radius <= 4096)) return rerror_set(e, "restir: radius %g outside [1, 4096]", o->radius);
    restir_neighbor_options_for(&no, o);
    if (neighbor_options_validate(&no, e)) return -1;
    if (neighbor_candidate_count(&no) + 1 > RESTIR_MAX_DOMAINS)
        return rerror_set(e, "restir: %d neighbour candidates per pixel (at most %d)", neighbor_candidate_count(&no),
                          RESTIR_MAX_DOMAINS - 1);
    if (!(o->time_limit >= 0) || !(o->time_limit < 1e9)) return rerror_set(e, "restir: time limit %g", o->time_limit);
    if (o->frames < 1) return rerror_set(e, "restir: %d frames", o->frames);
    if (o->first_frame < 0) return rerror_set(e, "restir: first frame %d < 0", o->first_frame);
    if (o->candidates < 1 || o->candidates > 1 << 16)
        return rerror_set(e, "restir: %d path trees (1..65536)", o->candidates);
    if ((uint64_t)(o->first_frame + (uint64_t)o->frames) * (uint64_t)o->candidates > UINT32_MAX)
        return rerror_set(e, "restir: frame range x path trees exceeds 2^32 sample indices");
    if (o->max_depth < min_depth || o->max_depth > PATH_MAX_LENGTH)
        return rerror_set(e, "restir: max depth %d outside %d..%d", o->max_depth, min_depth, PATH_MAX_LENGTH);
    if (!(o->roughness_threshold >= 0) || !(o->distance_threshold >= 0))
        return rerror_set(e, "restir: negative (or NaN) roughness or distance threshold");
    if (o->shading != RESTIR_SHADING_SCALAR && o->shading != RESTIR_SHADING_VECTOR)
        return rerror_set(e, "restir: unknown shading %d", o->shading);
    if (o->shading == RESTIR_SHADING_VECTOR && o->mis == RESTIR_MIS_STOCHASTIC_PAIRWISE)
        return rerror_set(e, "restir: --shading vector needs a deterministic spatial MIS family (the stochastic "
                             "pairwise step keeps no per-input weights to sum)");
    if (o->pairing != RESTIR_PAIRING_DISK && o->pairing != RESTIR_PAIRING_PAIRED)
        return rerror_set(e, "restir: unknown pairing %d", o->pairing);
    if (o->rc_criterion != RC_MODE_GRIS && o->rc_criterion != RC_MODE_FOOTPRINT)
        return rerror_set(e, "restir: unknown reconnection criterion %d", o->rc_criterion);
    if (!(o->footprint_c >= 0) || isinf(o->footprint_c))
        return rerror_set(e, "restir: footprint constant c %g (must be finite and >= 0)", o->footprint_c);
    if (o->paths != RESTIR_PATHS_ALL && o->paths != RESTIR_PATHS_INDIRECT)
        return rerror_set(e, "restir: unknown --paths %d", o->paths);
    if (o->ablation < 0 || o->ablation >= RESTIR_ABLATION_COUNT)
        return rerror_set(e, "restir: unknown ablation %d", o->ablation);
    if (o->ablation == RESTIR_ABLATE_PAIR_MIS && !restir_pair_step_active(o))
        return rerror_set(e, "restir: --ablate pair-mis needs the pair step (--pairing paired, a deterministic --mis, "
                             "no --reuse-cells, no --no-pair-step)");
    if (o->threads < 1) return rerror_set(e, "restir: %d threads", o->threads);
    if (o->temporal_mis < 0 || o->temporal_mis >= MIS_FAMILY_COUNT)
        return rerror_set(e, "restir: unknown temporal MIS family %d", o->temporal_mis);
    if (o->pairwise_confidence < 0 || o->pairwise_confidence > 1)
        return rerror_set(e, "restir: unknown pairwise confidence form %d", o->pairwise_confidence);
    if (o->mutations < 0 || o->mutations > MUTATE_MAX_ITERATIONS)
        return rerror_set(e, "restir: --mutations %d (must be 0..%d)", o->mutations, MUTATE_MAX_ITERATIONS);
    if (o->mutation < 0 || o->mutation >= MUTATE_STRATEGY_COUNT)
        return rerror_set(e, "restir: unknown mutation strategy %d", o->mutation);
    if (o->mutate_after & ~(MUTATE_AFTER_INITIAL | MUTATE_AFTER_TEMPORAL | MUTATE_AFTER_SPATIAL))
        return rerror_set(e, "restir: unknown mutation stage bits %#x", (unsigned)o->mutate_after);
    if (!(o->mcap > 0)) return rerror_set(e, "restir: M-cap %g (must be > 0, or inf)", o->mcap);
    if (o->light_ris < 0 || o->light_ris > LIGHT_RIS_MAX)
        return rerror_set(e, "restir: --light-ris %d is outside 0..%d candidates", o->light_ris, LIGHT_RIS_MAX);
    if (o->light_tiles && o->light_ris == 0) return rerror_set(e, "restir: --light-tiles needs --light-ris N");
    /* The MCMC mutations perturb the light point's two numbers (path_nee_numbers); under
     * light RIS the NEE vertex is a discrete choice among candidates, which they do not
     * define a mutation of (docs/enhanced.md §6). */
    if (o->light_ris > 0 && o->mutations > 0)
        return rerror_set(e, "restir: --mutations cannot be combined with --light-ris (no mutation of a light-RIS "
                             "NEE vertex is defined; docs/enhanced.md section 6)");
    return correlation_options_validate(o, e);
}

void restir_context_for(restir_context *c, const scene *s, const light_set *lights, const restir_options *o)
{
    memset(c, 0, sizeof *c);
    c->path.scene = s;
    c->path.lights = lights;
    c->path.strategy = PT_STRATEGY_MIS;
    c->path.ablations = o->ablation == RESTIR_ABLATE_LIGHT_RIS_PDF ? PT_ABLATE_LIGHT_RIS_PDF : 0;
    c->path.light_ris = o->light_ris;
    c->path.light_tiles = o->light_tiles;
    c->path.image_width = s->width;
    c->shift = o->shift;
    c->rc.roughness_threshold = (real)o->roughness_threshold;
    c->rc.min_distance = rc_min_distance_for_scene(s, (real)o->distance_threshold);
    c->rc.mode = o->rc_criterion;
    c->rc.footprint_c = (real)o->footprint_c;
    c->rc.force_nee = o->force_nee_reconnection != 0;
    c->ablation = o->ablation;
}

void restir_initial_options_for(initial_options *io, const restir_options *o)
{
    io->trees = o->candidates;
    io->max_depth = o->max_depth;
    io->indirect_only = o->paths == RESTIR_PATHS_INDIRECT;
    io->russian_roulette = o->russian_roulette;
    io->rr_min_depth = o->rr_min_depth;
}

void restir_options_write_json(FILE *out, const restir_options *o, const char *indent)
{
    fprintf(out, "{\"shift\": \"%s\", \"mis\": \"%s\", \"candidates\": %d, \"spatial_passes\": %d, ",
            restir_shift_names[o->shift], restir_mis_names[o->mis], o->candidates, o->spatial_passes);
    fprintf(out, "\"neighbors\": %d, \"radius\": %g, \"pattern\": \"%s\", \"reject\": %s, \"normal_cos\": %g, "
                 "\"depth_ratio\": %g,\n%s  ",
            o->neighbors, o->radius, neighbor_pattern_names[o->pattern], o->no_reject ? "false" : "true",
            o->normal_cos, o->depth_ratio, indent);
    fprintf(out, "\"frames\": %d, \"first_frame\": %d, \"time_limit\": %g, \"max_depth\": %d, "
                 "\"roughness_threshold\": %g, \"distance_threshold\": %g, \"paths\": \"%s\", \"ablate\": \"%s\", ",
            o->frames, o->first_frame, o->time_limit, o->max_depth, o->roughness_threshold, o->distance_threshold,
            restir_paths_names[o->paths], restir_ablation_names[o->ablation]);
    fprintf(out, "\"pairing\": \"%s\", \"pair_step\": %s, \"shading\": \"%s\", ", restir_pairing_names[o->pairing],
            restir_pair_step_active(o) ? "true" : "false", restir_shading_names[o->shading]);
    fprintf(out, "\"force_nee_reconnection\": %s, ", o->force_nee_reconnection ? "true" : "false");
    fprintf(out, "\"rc_criterion\": \"%s\", \"footprint_c\": %g, ", rc_mode_names[o->rc_criterion], o->footprint_c);
    fprintf(out, "\"russian_roulette\": %s, \"jitter\": %s, \"seed\": %u, \"threads\": %d,\n%s  ",
            o->russian_roulette ? "true" : "false", o->jitter ? "true" : "false", o->seed, o->threads, indent);
    if (o->mis == RESTIR_MIS_STOCHASTIC_PAIRWISE || o->cells) /* issue 14 (only when used) */
        fprintf(out, "\"stochastic_n\": %d, \"stochastic_nc\": %d, \"confidence_scaling\": %s, \"reuse_cells\": %s,\n%s  ",
                o->stochastic_n, o->stochastic_nc, o->no_confidence_scaling ? "false" : "true", o->cells ? "true" : "false",
                indent);
    if (o->dedup || o->motion_vectors || o->boiling_filter > 0) /* issue 12 (only when used) */
        fprintf(out, "\"dedup\": %s, \"dedup_min\": %g, \"dedup_alpha\": %g, \"motion_vectors\": \"%s\", "
                     "\"boiling_filter\": %g, \"biased\": %s,\n%s  ",
                o->dedup ? "true" : "false", o->dedup_min, o->dedup_alpha, restir_motion_vector_names[o->motion_vectors],
                o->boiling_filter, restir_options_biased(o) ? "true" : "false", indent);
    if (isinf(o->mcap))
        fprintf(out, "\"temporal\": %s, \"temporal_mis\": \"%s\", \"mcap\": \"inf\"", o->temporal ? "true" : "false",
                restir_mis_names[o->temporal_mis]);
    else
        fprintf(out, "\"temporal\": %s, \"temporal_mis\": \"%s\", \"mcap\": %g", o->temporal ? "true" : "false",
                restir_mis_names[o->temporal_mis], o->mcap);
    if (o->pairwise_confidence) /* issue 31 (only when used) */
        fprintf(out, ", \"pairwise_confidence\": \"%s\"", restir_pairwise_confidence_names[o->pairwise_confidence]);
    fprintf(out, ", \"mutations\": %d, \"mutation\": \"%s\", \"mutate_after\": %d, \"light_ris\": %d, \"light_tiles\": %s}", o->mutations,
            mutate_strategy_names[o->mutation], o->mutate_after, o->light_ris, o->light_tiles ? "true" : "false");
}
