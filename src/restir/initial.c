/* Initial resampling over N path trees (include/restir/restir/initial.h). */
#include "restir/restir/initial.h"

#include <string.h>
#include "restir/restir/path_replay.h"
#include "restir/restir/reconnection.h"

/* The candidate currently held by the stream (its identity is enough: path_record
 * rebuilds everything else from it). */
typedef struct {
    real wsum;
    uint32_t n_invalid;
    int selected;
    uint32_t sample;
    int length, technique;
    rgb F;
} candidate_stream;

uint32_t initial_tree_sample(const initial_options *o, uint32_t frame, int tree)
{
    return frame * (uint32_t)o->trees + (uint32_t)tree;
}

rng_key initial_pixel_key(const initial_options *o, uint32_t seed, uint32_t frame, uint32_t pixel)
{
    return rng_key_make(seed, pixel, initial_tree_sample(o, frame, 0));
}

/* GRIS Eq. 1 with M -> N trees and W_x = 1 / roulette survival probability (the RIS
 * weight p̂/p of Stochastic MIS Eq. 2, with the 1/N of the N canonical trees). The key by
 * address and the number by rng_u_slots (rng_u's number bit for bit): a key passed by value
 * or built by rng_key_at is copied to the stack just after its narrow stores, and that
 * reload stalled the candidate loop (docs/performance.md, issue 28). */
static void offer(candidate_stream *cs, const initial_options *o, const rng_key *key, uint32_t sample, int d,
                  int technique, rgb F, real rr_survival, initial_stats *st)
{
    real w, u;
    if (d < 2 || (o->indirect_only && d < 3)) return;
    w = ris_candidate_weight(luminance(F), 1 / rr_survival, (real)o->trees);
    rng_u_slots(*key, RNG_RIS, RNG_VERTEX_INITIAL_RIS(d), (uint32_t)technique, 1, &u);
    if (w > 0) st->candidates++;
    if (!wrs_update(&cs->wsum, w, u, &cs->n_invalid)) return;
    cs->selected = 1;
    cs->sample = sample;
    cs->length = d;
    cs->technique = technique;
    cs->F = F;
}

/* The reference path tracer's roulette at x_i (pt.c): continue with probability
 * q = min(1, max channel of the roulette-compensated throughput), RNG_RR at (i, 0).
 * Returns q (1 if no roulette happens here) or 0 to stop. */
static real roulette(const initial_options *o, rng_key key, int i, rgb *beta_rr)
{
    real q;
    if (!o->russian_roulette || i < o->rr_min_depth) return 1;
    q = rgb_max(*beta_rr);
    if (q >= 1) return 1;
    if (rng_u(key, RNG_RR, (uint32_t)i, 0) >= q) return 0;
    *beta_rr = rgb_scale(*beta_rr, 1 / q);
    return q;
}

/* The BSDF path ending at the emitter `hit`, reached by bounce b (sample record rec) from
 * x_i = `from`, as a candidate. The all-lobe pdf of b (its MIS weight, GRIS §7.6) is
 * computed only here, as the path tracer does: most bounces reach no emitter. */
static void offer_emitter(const restir_context *c, const initial_options *o, const rng_key *key, uint32_t sample,
                          int i, rgb beta_hit, const path_vertex *from, const path_vertex *hit, bsdf_bounce *b,
                          const bsdf_sample_record *rec, real survival, candidate_stream *cs, initial_stats *st)
{
    real light_pdf;
    rgb le = path_vertex_emitted(&c->path, hit), F;
    if (rgb_is_black(le)) return;
    b->pdf_all = path_bounce_pdf_all(from, rec);
    F = emitted_path_contribution(&c->path, le, beta_hit, from, hit, b, *key, i, &light_pdf);
    if (!rgb_is_black(F)) offer(cs, o, key, sample, i + 1, PATH_TECH_BSDF, F, survival, st);
}

/* One path tree: the loop of the reference path tracer (pt.c trace_path), where every
 * increment to the pixel becomes a candidate instead. Like that loop it keeps x_i and
 * x_{i+1} only (x1 read in place, never copied). Its steps compute what a path_trunk's do,
 * in the same order (path_bsdf_numbers's numbers, trunk_sample's sample and product,
 * trunk_trace_escape's path_trace_bounce), so path_record rebuilds the selected path bit
 * for bit (restir_initial_tree_is_the_path_tracer_tree checks it). */
static void stream_tree(const restir_context *c, const initial_options *o, const path_vertex *x1, uint32_t seed,
                        uint32_t pixel, uint32_t sample, candidate_stream *cs, initial_stats *st)
{
    rng_key key = rng_key_make(seed, pixel, sample);
    path_vertex pair[2], *next = &pair[0];
    const path_vertex *v = x1; /* x_i */
    rgb beta = rgb_gray(1);    /* the trunk's PSS throughput arriving at x_i (no roulette) */
    rgb beta_rr = rgb_gray(1); /* the path tracer's throughput, roulette compensated */
    real survival = 1;         /* product of the roulette continuation probabilities */
    int i;
    for (i = 1; i < o->max_depth; ++i) {
        bsdf_bounce b;
        bsdf_sample_record rec;
        rgb beta_next;
        real q;
        if (v->can_nee && !(o->indirect_only && i + 1 < 3)) {
            nee_sample n;
            if (vertex_sample_light(&c->path, v, &key, (uint32_t)i, &n))
                offer(cs, o, &key, sample, i + 1, PATH_TECH_NEE, nee_path_contribution(&c->path, beta, &n), survival,
                      st);
        }
        /* A tree's identity has no explicit numbers: path_bsdf_numbers gives its RNG_BSDF
         * numbers, which vertex_sample_bsdf draws from the same key. */
        if (!vertex_sample_bsdf(v, &key, (uint32_t)i, &b, &rec)) break;
        beta_next = rgb_mul(beta, b.weight); /* trunk_sample's product */
        if (rgb_is_black(beta_next)) break;
        beta_rr = rgb_mul(beta_rr, b.weight);
        if (rgb_is_black(beta_rr)) break;
        if ((q = roulette(o, key, i, &beta_rr)) == 0) break;
        survival *= q;
        /* A ray that leaves the scene ends the path at the sky (docs/environment.md). */
        if (path_trace_bounce(c->path.scene, c->path.lights, v, &b, next) != SHIFT_OK) break;
        offer_emitter(c, o, &key, sample, i, beta_next, v, next, &b, &rec, survival, cs, st);
        if (path_vertex_is_distant(next)) break;
        /* x_{i+1} becomes x_i; the other slot of the pair takes x_{i+2} (never x1's). */
        v = next;
        next = next == &pair[0] ? &pair[1] : &pair[0];
        beta = beta_next;
    }
}

static int rgb_equal(rgb a, rgb b) { return a.r == b.r && a.g == b.g && a.b == b.b; }

void initial_sample_pixel(const restir_context *c, const initial_options *o, const path_vertex *x1, uint32_t seed,
                          uint32_t pixel, uint32_t frame, reservoir *r, initial_stats *st)
{
    candidate_stream cs;
    int tree;
    memset(&cs, 0, sizeof cs);
    reservoir_init(r);
    st->pixels++;
    for (tree = 0; tree < o->trees; ++tree) {
        stream_tree(c, o, x1, seed, pixel, initial_tree_sample(o, frame, tree), &cs, st);
        st->trees++;
    }
    r->wsum = cs.wsum;
    r->n_invalid = cs.n_invalid;
    reservoir_add_confidence(r, (real)o->trees); /* c = N (GRIS §6.2, Enhanced §2.2) */
    if (cs.selected) {
        path_sample_begin(&r->y, seed, pixel, cs.sample);
        r->y.length = (uint8_t)cs.length;
        r->y.technique = (uint8_t)cs.technique;
        if (path_record(c, x1, &r->y) != SHIFT_OK) {
            st->record_failed++; /* cannot happen: the same code replays the same numbers */
            reservoir_init(r);
            return;
        }
        if (!rgb_equal(r->y.F, cs.F)) st->record_mismatch++;
        path_sample_set_contribution(&r->y, cs.F); /* the value the weights were computed with */
        if (r->y.rc_flags & PATH_RC_FLAG_UNSHIFTABLE) st->unshiftable++;
        st->selected++;
        st->length[r->y.length]++;
        st->rc_index[r->y.rc_k]++;
    }
    reservoir_finalize(r); /* W = sum w / p̂(Y), GRIS Eq. 22 */
    st->invalid_weights += r->n_invalid;
}

void initial_stats_add(initial_stats *acc, const initial_stats *add)
{
    int i;
    acc->pixels += add->pixels;
    acc->trees += add->trees;
    acc->candidates += add->candidates;
    acc->selected += add->selected;
    acc->record_failed += add->record_failed;
    acc->record_mismatch += add->record_mismatch;
    acc->invalid_weights += add->invalid_weights;
    acc->unshiftable += add->unshiftable;
    for (i = 0; i <= PATH_MAX_LENGTH; ++i) {
        acc->length[i] += add->length[i];
        acc->rc_index[i] += add->rc_index[i];
    }
}
