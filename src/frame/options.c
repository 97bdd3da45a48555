/* The ReSTIR PT run configuration (include/restir/frame/options.h): defaults, the GRIS
 * §8.3 presets, validation, and what each estimator module is handed of it. */
#include "restir/frame/options.h"

#include <math.h>
#include <string.h>
#include "restir/render/light_ris.h"
#include "restir/restir/connectability.h"

/* every spatial pass has its own RNG_RIS vertices (rng.h) */
typedef char passes_have_vertices[RESTIR_MAX_SPATIAL_PASSES <= RNG_VERTEX_PASSES ? 1 : -1];

const char *const restir_paths_names[] = {"all", "indirect", NULL};
const char *const restir_shading_names[] = {"scalar", "vector", NULL};

void restir_options_default(restir_options *o)
{
    memset(o, 0, sizeof *o);
    o->shift = RESTIR_SHIFT_HYBRID;
    o->spatial_passes = 0;
    spatial_options_default(&o->spatial);
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
    temporal_options_default(&o->temporal);
    stochastic_options_default(&o->stochastic);
    correlation_options_default(&o->correlation);
    mutation_options_default(&o->mutation);
    light_ris_options_default(&o->light_ris);
}

int restir_pairing_build(neighbor_options *no, const restir_options *o, reuse_texture *textures, rerror *e)
{
    no->textures = NULL;
    if (no->pattern != NEIGHBOR_PAIRED) return 0;
    if (reuse_textures_build_as(textures, no->count, pairing_sigma_for_radius(o->spatial.radius), o->spatial.eq3_reading,
                                o->seed, e))
        return -1;
    no->textures = textures;
    return 0;
}

int restir_pair_step_active(const restir_options *o)
{
    return o->spatial.pairing == RESTIR_PAIRING_PAIRED && !o->no_pair_step &&
           o->spatial.algorithm == SPATIAL_GRIS_STEP && !o->spatial.cells && o->spatial_passes > 0;
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
    o->spatial_passes = 3;
    o->spatial.neighbors = 6;
    o->spatial.radius = 10;
    o->spatial.mis = MIS_PAIRWISE_DEFENSIVE;
}

void restir_options_preset_gris_realtime(restir_options *o)
{
    o->candidates = 1;
    o->temporal.enabled = 1;
    o->temporal.mis = MIS_TALBOT;
    o->temporal.mcap = 20;
    o->spatial_passes = 1;
    o->spatial.neighbors = 3;
    o->spatial.radius = 20;
    o->spatial.mis = MIS_PAIRWISE_DEFENSIVE;
}

int restir_options_biased(const restir_options *o) { return correlation_options_biased(&o->correlation); }

const char *const restir_pairwise_confidence_names[] = {"stochastic", "falcor", NULL};

mis_family restir_step_mis(const restir_options *o, int mis)
{
    if (mis == MIS_PAIRWISE_DEFENSIVE && o->pairwise_confidence == 1) return MIS_PAIRWISE_DEFENSIVE_FALCOR;
    return (mis_family)mis;
}

/* Each technique checks its own options (its message names it). */
static int techniques_validate(const restir_options *o, rerror *e)
{
    if (spatial_options_validate(&o->spatial, e) || temporal_options_validate(&o->temporal, e) ||
        stochastic_options_validate(&o->stochastic, e) || mutation_options_validate(&o->mutation, e) ||
        correlation_options_validate(&o->correlation, e) || light_ris_options_validate(&o->light_ris, e))
        return -1;
    return 0;
}

/* The rules between techniques, and between a technique and the frame. */
static int combinations_validate(const restir_options *o, rerror *e)
{
    neighbor_options no;
    spatial_neighbor_options(&no, &o->spatial);
    if (neighbor_candidate_count(&no) + 1 > RESTIR_MAX_DOMAINS)
        return rerror_set(e, "restir: %d neighbour candidates per pixel (at most %d)", neighbor_candidate_count(&no),
                          RESTIR_MAX_DOMAINS - 1);
    if (o->shading == RESTIR_SHADING_VECTOR && o->spatial.algorithm == SPATIAL_STOCHASTIC_PAIRWISE)
        return rerror_set(e, "restir: vector shading needs the spatial GRIS step with a MIS family (the stochastic "
                             "pairwise step keeps no per-input weights to sum)");
    if (o->ablation == RESTIR_ABLATE_PAIR_MIS && !restir_pair_step_active(o))
        return rerror_set(e, "restir: the pair-mis ablation needs the pair step (paired reuse, the GRIS step with a "
                             "MIS family, no reuse cells, the pair step not turned off, spatial passes > 0)");
    /* Issue 12 (docs/correlation.md): the adaptive cap lowers the temporal cap towards
     * c_cap_min; an infinite cap has nothing to interpolate from. */
    if (o->correlation.dedup && isinf(o->temporal.mcap))
        return rerror_set(e, "restir: the dedup cap needs a finite temporal M-cap (got %g)", o->temporal.mcap);
    /* The MCMC mutations perturb the light point's two numbers (path_nee_numbers); under
     * light RIS the NEE vertex is a discrete choice among candidates, which they do not
     * define a mutation of (docs/enhanced.md §6). */
    if (o->light_ris.candidates > 0 && o->mutation.count > 0)
        return rerror_set(e, "restir: mutations cannot be combined with light RIS (no mutation of a light-RIS "
                             "NEE vertex is defined; docs/enhanced.md section 6)");
    return 0;
}

int restir_options_validate(const restir_options *o, rerror *e)
{
    int min_depth = o->paths == RESTIR_PATHS_INDIRECT ? 3 : 2;
    if (o->shift < 0 || o->shift >= RESTIR_SHIFT_COUNT) return rerror_set(e, "restir: unknown shift %d", o->shift);
    if (o->spatial_passes < 0 || o->spatial_passes > RESTIR_MAX_SPATIAL_PASSES)
        return rerror_set(e, "restir: %d spatial passes (0..%d)", o->spatial_passes, RESTIR_MAX_SPATIAL_PASSES);
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
    if (o->rc_criterion != RC_MODE_GRIS && o->rc_criterion != RC_MODE_FOOTPRINT)
        return rerror_set(e, "restir: unknown reconnection criterion %d", o->rc_criterion);
    if (!(o->footprint_c >= 0) || isinf(o->footprint_c))
        return rerror_set(e, "restir: footprint constant c %g (must be finite and >= 0)", o->footprint_c);
    if (o->paths != RESTIR_PATHS_ALL && o->paths != RESTIR_PATHS_INDIRECT)
        return rerror_set(e, "restir: unknown path set %d", o->paths);
    if (o->ablation < 0 || o->ablation >= RESTIR_ABLATION_COUNT)
        return rerror_set(e, "restir: unknown ablation %d", o->ablation);
    if (o->threads < 1) return rerror_set(e, "restir: %d threads", o->threads);
    if (o->pairwise_confidence < 0 || o->pairwise_confidence > 1)
        return rerror_set(e, "restir: unknown pairwise confidence form %d", o->pairwise_confidence);
    if (techniques_validate(o, e)) return -1;
    return combinations_validate(o, e);
}

void restir_context_for(restir_context *c, const scene *s, const light_set *lights, const restir_options *o)
{
    memset(c, 0, sizeof *c);
    c->path.scene = s;
    c->path.lights = lights;
    c->path.strategy = PT_STRATEGY_MIS;
    c->path.ablations = o->ablation == RESTIR_ABLATE_LIGHT_RIS_PDF ? PT_ABLATE_LIGHT_RIS_PDF : 0;
    c->path.light_ris = o->light_ris.candidates;
    c->path.light_tiles = o->light_ris.tiles;
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
    const spatial_options *sp = &o->spatial;
    const temporal_options *tp = &o->temporal;
    const correlation_options *co = &o->correlation;
    fprintf(out, "{\"shift\": \"%s\", \"mis\": \"%s\", \"candidates\": %d, \"spatial_passes\": %d, ",
            restir_shift_names[o->shift], spatial_mis_name(sp), o->candidates, o->spatial_passes);
    fprintf(out, "\"neighbors\": %d, \"radius\": %g, \"pattern\": \"%s\", \"reject\": %s, \"normal_cos\": %g, "
                 "\"depth_ratio\": %g,\n%s  ",
            sp->neighbors, sp->radius, neighbor_pattern_names[sp->pattern], sp->no_reject ? "false" : "true",
            sp->normal_cos, sp->depth_ratio, indent);
    fprintf(out, "\"frames\": %d, \"first_frame\": %d, \"time_limit\": %g, \"max_depth\": %d, "
                 "\"roughness_threshold\": %g, \"distance_threshold\": %g, \"paths\": \"%s\", \"ablate\": \"%s\", ",
            o->frames, o->first_frame, o->time_limit, o->max_depth, o->roughness_threshold, o->distance_threshold,
            restir_paths_names[o->paths], restir_ablation_names[o->ablation]);
    fprintf(out, "\"pairing\": \"%s\", \"pair_step\": %s, \"shading\": \"%s\", ", restir_pairing_names[sp->pairing],
            restir_pair_step_active(o) ? "true" : "false", restir_shading_names[o->shading]);
    fprintf(out, "\"force_nee_reconnection\": %s, ", o->force_nee_reconnection ? "true" : "false");
    fprintf(out, "\"rc_criterion\": \"%s\", \"footprint_c\": %g, ", rc_mode_names[o->rc_criterion], o->footprint_c);
    fprintf(out, "\"russian_roulette\": %s, \"jitter\": %s, \"seed\": %u, \"threads\": %d,\n%s  ",
            o->russian_roulette ? "true" : "false", o->jitter ? "true" : "false", o->seed, o->threads, indent);
    if (sp->algorithm == SPATIAL_STOCHASTIC_PAIRWISE || sp->cells) /* issue 14 (only when used) */
        fprintf(out, "\"stochastic_n\": %d, \"stochastic_nc\": %d, \"confidence_scaling\": %s, \"reuse_cells\": %s,\n%s  ",
                o->stochastic.n_picks, o->stochastic.n_canonical_picks, o->stochastic.confidence_scaling ? "true" : "false",
                sp->cells ? "true" : "false", indent);
    if (co->dedup || tp->motion_vectors || co->boiling_filter > 0) /* issue 12 (only when used) */
        fprintf(out, "\"dedup\": %s, \"dedup_min\": %g, \"dedup_alpha\": %g, \"motion_vectors\": \"%s\", "
                     "\"boiling_filter\": %g, \"biased\": %s,\n%s  ",
                co->dedup ? "true" : "false", co->dedup_min, co->dedup_alpha, restir_motion_vector_names[tp->motion_vectors],
                co->boiling_filter, restir_options_biased(o) ? "true" : "false", indent);
    if (isinf(tp->mcap))
        fprintf(out, "\"temporal\": %s, \"temporal_mis\": \"%s\", \"mcap\": \"inf\"", tp->enabled ? "true" : "false",
                restir_mis_names[tp->mis]);
    else
        fprintf(out, "\"temporal\": %s, \"temporal_mis\": \"%s\", \"mcap\": %g", tp->enabled ? "true" : "false",
                restir_mis_names[tp->mis], tp->mcap);
    if (tp->mcap_mode != TEMPORAL_MCAP_RELATIVE) /* issue 28 (only when used) */
        fprintf(out, ", \"mcap_mode\": \"%s\"", temporal_mcap_mode_names[tp->mcap_mode]);
    if (sp->pairing == RESTIR_PAIRING_PAIRED) /* issue 28: which Eq. 3 reading made the textures */
        fprintf(out, ", \"eq3_reading\": \"%s\"", pairing_eq3_names[sp->eq3_reading]);
    if (o->mutation.kernel != MUTATE_KERNEL_KELEMEN) /* issue 28 (only when used) */
        fprintf(out, ", \"mutation_kernel\": \"%s\", \"mutation_sigma\": %g", mutate_kernel_names[o->mutation.kernel],
                o->mutation.sigma);
    if (o->pairwise_confidence) /* issue 31 (only when used) */
        fprintf(out, ", \"pairwise_confidence\": \"%s\"", restir_pairwise_confidence_names[o->pairwise_confidence]);
    fprintf(out, ", \"mutations\": %d, \"mutation\": \"%s\", \"mutate_after\": %d, \"light_ris\": %d, \"light_tiles\": %s}",
            o->mutation.count, mutate_strategy_names[o->mutation.strategy], o->mutation.stages,
            o->light_ris.candidates, o->light_ris.tiles ? "true" : "false");
}
