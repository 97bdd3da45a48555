/* Path-sample invariants and the reservoir dump format (docs/formats.md): round trips,
 * the documented byte offsets, and strict rejection of malformed files. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "restir/restir/reservoir_dump.h"
#include "test.h"

static real dump_urand(rng_key key, uint32_t *n)
{
    real u = rng_u(key, RNG_TEST, 0, *n);
    (*n)++;
    return u;
}

static vec3 random_unit(rng_key key, uint32_t *n)
{
    vec3 v = v3(dump_urand(key, n) - (real)0.5, dump_urand(key, n) - (real)0.5, (real)0.1 + dump_urand(key, n));
    return v3_normalize(v);
}

/* A random sample that satisfies every invariant of path_sample.h; with explicit numbers
 * (kept in pss[PATH_MAX_PSS]) unless pss is NULL. */
static void random_path_sample(path_sample *s, uint32_t index, real *pss)
{
    rng_key key = rng_key_make(test_seed(), index, 99);
    uint32_t n = 0;
    int d, j;
    path_sample_begin(s, test_seed(), index * 7u, index);
    d = 2 + (int)(dump_urand(key, &n) * (PATH_MAX_LENGTH - 1));
    s->length = (uint8_t)d;
    s->technique = dump_urand(key, &n) < 0.5 ? PATH_TECH_NEE : PATH_TECH_BSDF;
    for (j = 1; j < d; ++j) s->lobe[j] = (uint8_t)(dump_urand(key, &n) < 0.5 ? 0 : 1);
    if (s->technique == PATH_TECH_NEE) s->lobe[d - 1] = PATH_LOBE_NEE;
    s->rc_k = dump_urand(key, &n) < 0.2 ? PATH_RC_NONE : (uint8_t)(2 + (int)(dump_urand(key, &n) * (d - 1)));
    if (s->rc_k != PATH_RC_NONE) {
        s->rc_triangle = index * 31u + 5u;
        s->rc_bary[0] = (float)dump_urand(key, &n) * 0.5f;
        s->rc_bary[1] = (float)dump_urand(key, &n) * 0.5f;
        s->rc_position = v3f((float)dump_urand(key, &n), -2.5f, (float)index);
        s->rc_normal = v3f_from(random_unit(key, &n));
        s->rc_normal = v3f_normalize(s->rc_normal);
        s->rc_wo = s->rc_k < d ? random_unit(key, &n) : v3(0, 0, 0);
        s->rc_pdf_prev = 10 * dump_urand(key, &n);
        s->rc_geom = dump_urand(key, &n) / 3;
        s->rc_pdf = s->rc_k == d ? 1 : 4 * dump_urand(key, &n);
        s->rc_radiance = rgb_make(dump_urand(key, &n), 2 * dump_urand(key, &n), 0);
        s->rc_flags = dump_urand(key, &n) < 0.3 ? PATH_RC_FLAG_UNSHIFTABLE : 0;
    }
    s->light_pdf = dump_urand(key, &n);
    path_sample_set_contribution(s, rgb_make(dump_urand(key, &n), dump_urand(key, &n) / 7, 3));
    if (pss) {
        memset(pss, 0, PATH_MAX_PSS * sizeof *pss);
        s->pss = pss;
        s->n_pss = (uint8_t)(dump_urand(key, &n) * (PATH_MAX_PSS + 1));
        for (j = 0; j < s->n_pss; ++j) s->pss[j] = dump_urand(key, &n);
    }
}

static void random_reservoir(reservoir *r, uint32_t index, real *pss)
{
    reservoir_init(r);
    if (index % 5 == 3) return; /* some empty reservoirs */
    random_path_sample(&r->y, index, pss);
    r->wsum = (real)index * (real)0.25;
    r->W = (real)index / 3;
    r->confidence = (real)(index % 20) + (real)0.5;
    r->n_invalid = index % 3;
}

TEST(path_sample_invariants)
{
    path_sample s, bad;
    rerror e;
    real numbers[PATH_MAX_PSS], bad_numbers[PATH_MAX_PSS];
    uint32_t i;
    path_sample_clear(&s);
    CHECK(path_sample_check(&s, "empty", &e) == 0);
    CHECK(!path_sample_is_valid(&s));
    for (i = 0; i < 200; ++i) {
        random_path_sample(&s, i, numbers);
        CHECKF(path_sample_check(&s, "random", &e) == 0, "%s", e.msg);
        CHECK(s.target == luminance(s.F));
    }
    s.length = 5;
    s.technique = PATH_TECH_NEE;
    memset(s.lobe, PATH_LOBE_NONE, sizeof s.lobe);
    s.lobe[1] = 0;
    s.lobe[2] = 1;
    s.lobe[3] = 0;
    s.lobe[4] = PATH_LOBE_NEE;
    s.rc_k = 3;
    s.rc_wo = v3(0, 0, 1);
    s.rc_normal = v3f(0, 1, 0);
    CHECKF(path_sample_check(&s, "hand", &e) == 0, "%s", e.msg);
    CHECK(path_sample_rc_lobe(&s) == 0);
    CHECK(rng_bits(rng_key_at(path_sample_key(&s), RNG_BSDF, 1, 0)) ==
          rng_bits(rng_key_at(rng_key_make(s.seed, s.pixel, s.sample), RNG_BSDF, 1, 0)));
    bad = s; bad.rc_k = 6; CHECK(path_sample_check(&bad, "k > d", &e) != 0);
    bad = s; bad.rc_k = 1; CHECK(path_sample_check(&bad, "k = 1", &e) != 0);
    bad = s; bad.length = 1; CHECK(path_sample_check(&bad, "d = 1", &e) != 0);
    bad = s; bad.length = 17; CHECK(path_sample_check(&bad, "d = 17", &e) != 0);
    bad = s; bad.technique = 3; CHECK(path_sample_check(&bad, "technique", &e) != 0);
    bad = s; bad.lobe[4] = 0; CHECK(path_sample_check(&bad, "NEE lobe missing", &e) != 0);
    bad = s; bad.lobe[5] = 0; CHECK(path_sample_check(&bad, "lobe past x_{d-1}", &e) != 0);
    bad = s; bad.lobe[0] = 0; CHECK(path_sample_check(&bad, "lobe at camera", &e) != 0);
    bad = s; bad.technique = PATH_TECH_BSDF; CHECK(path_sample_check(&bad, "NEE lobe on BSDF path", &e) != 0);
    bad = s; bad.rc_normal = v3f(0, 2, 0); CHECK(path_sample_check(&bad, "normal", &e) != 0);
    bad = s; bad.rc_wo = v3(0, 0, 0); CHECK(path_sample_check(&bad, "omega_k", &e) != 0);
    bad = s; bad.rc_pdf = -1; CHECK(path_sample_check(&bad, "pdf", &e) != 0);
    bad = s; bad.F.g = (real)NAN; CHECK(path_sample_check(&bad, "F", &e) != 0);
    bad = s; bad.rc_flags = 0x2; CHECK(path_sample_check(&bad, "unknown rc flag", &e) != 0);
    bad = s; bad.rc_k = PATH_RC_NONE; bad.rc_flags = PATH_RC_FLAG_UNSHIFTABLE;
    CHECK(path_sample_check(&bad, "rc flag without k", &e) != 0);
    bad = s; bad.pss = bad_numbers; bad.n_pss = 2; bad.pss[0] = 0; bad.pss[1] = 1; CHECK(path_sample_check(&bad, "pss", &e) != 0);
    CHECKF(strstr(e.msg, "pss[1]") != NULL, "%s", e.msg);
}

/* Write + read gives back every field bit for bit (compared through the encoding), with
 * and without the primary-sample vectors. */
TEST(reservoir_dump_roundtrip)
{
    enum { W = 7, H = 5 };
    reservoir rs[W * H], *back = NULL;
    static real rows[W * H][PATH_MAX_PSS]; /* the samples' numbers (path_sample.h) */
    reservoir_dump_info info, got;
    unsigned char a[RESERVOIR_DUMP_RECORD_PSS], b[RESERVOIR_DUMP_RECORD_PSS];
    rerror e;
    int pass, i;
    for (pass = 0; pass < 2; ++pass) {
        const char *path = test_tmp_path(pass ? "dump-pss.bin" : "dump.bin");
        uint32_t flags = pass ? RESERVOIR_DUMP_FLAG_PSS : 0;
        for (i = 0; i < W * H; ++i) random_reservoir(&rs[i], (uint32_t)i, pass ? rows[i] : NULL);
        memset(&info, 0, sizeof info);
        info.width = W;
        info.height = H;
        info.frame = 12;
        strcpy(info.tag, pass ? "spatial1" : "initial");
        CHECKF(reservoir_dump_write(path, rs, &info, &e) == 0, "%s", e.msg);
        CHECKF(reservoir_dump_read(path, &back, &got, &e) == 0, "%s", e.msg);
        CHECK(got.width == W && got.height == H && got.frame == 12 && got.flags == flags);
        CHECK(got.real_bits == 8 * sizeof(real));
        CHECK(strcmp(got.tag, info.tag) == 0);
        for (i = 0; i < W * H; ++i) {
            reservoir_record_encode(&rs[i], flags, a);
            reservoir_record_encode(&back[i], flags, b);
            CHECKF(memcmp(a, b, reservoir_record_size(flags)) == 0, "record %d differs", i);
            CHECK(back[i].y.target == rs[i].y.target && back[i].W == rs[i].W);
            CHECK(back[i].y.n_pss == rs[i].y.n_pss);
        }
        free(back);
        back = NULL;
    }
}

static double le_f64(const unsigned char *p)
{
    uint64_t bits = 0;
    double d;
    int i;
    for (i = 0; i < 8; ++i) bits |= (uint64_t)p[i] << (8 * i);
    memcpy(&d, &bits, sizeof d);
    return d;
}

static uint32_t le_u32(const unsigned char *p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

static float le_f32(const unsigned char *p)
{
    uint32_t bits = le_u32(p);
    float f;
    memcpy(&f, &bits, sizeof f);
    return f;
}

/* The offsets of docs/formats.md, read back with an independent little-endian decoder. */
TEST(reservoir_dump_documented_offsets)
{
    reservoir r;
    unsigned char rec[RESERVOIR_DUMP_RECORD_PSS];
    real numbers[PATH_MAX_PSS];
    reservoir_init(&r);
    random_path_sample(&r.y, 3, numbers);
    r.y.length = 6;
    r.y.technique = PATH_TECH_BSDF;
    memset(r.y.lobe, PATH_LOBE_NONE, sizeof r.y.lobe);
    r.y.lobe[1] = 1;
    r.y.lobe[5] = 0;
    r.y.rc_k = 4;
    r.y.n_pss = 45;
    r.y.pss[44] = (real)0.75;
    r.y.rc_triangle = 0xA1B2C3D4u;
    r.y.rc_bary[1] = 0.125f;
    r.y.rc_position = v3f(1, 2, 3);
    r.y.rc_normal = v3f(0, 0, -1);
    r.y.rc_wo = v3(0, 1, 0);
    r.y.rc_pdf_prev = 11;
    r.y.rc_geom = 12;
    r.y.rc_pdf = 13;
    r.y.rc_radiance = rgb_make(14, 15, 16);
    r.y.light_pdf = 17;
    r.y.rc_flags = PATH_RC_FLAG_UNSHIFTABLE;
    path_sample_set_contribution(&r.y, rgb_make(18, 19, 20));
    r.y.seed = 0x01020304u;
    r.y.pixel = 77;
    r.y.sample = 88;
    r.wsum = 1.5;
    r.W = 2.5;
    r.confidence = 3.5;
    r.n_invalid = 9;
    CHECK(reservoir_record_size(0) == 216 && reservoir_record_size(RESERVOIR_DUMP_FLAG_PSS) == 576);
    reservoir_record_encode(&r, RESERVOIR_DUMP_FLAG_PSS, rec);
    CHECK(le_f64(rec + 0) == 1.5 && le_f64(rec + 8) == 2.5 && le_f64(rec + 16) == 3.5);
    CHECK(le_u32(rec + 24) == 9 && le_u32(rec + 28) == 0);
    CHECK(le_u32(rec + 32) == 0x01020304u && le_u32(rec + 36) == 77 && le_u32(rec + 40) == 88);
    CHECK(rec[44] == 6 && rec[45] == PATH_TECH_BSDF && rec[46] == 4 && rec[47] == 45);
    CHECK(rec[48] == 0xFF && rec[49] == 1 && rec[53] == 0 && rec[54] == 0xFF && rec[63] == 0xFF);
    CHECK(le_u32(rec + 64) == 0xA1B2C3D4u && le_f32(rec + 72) == 0.125f);
    CHECK(le_f32(rec + 76) == 1 && le_f32(rec + 80) == 2 && le_f32(rec + 84) == 3);
    CHECK(le_f32(rec + 96) == -1 && le_u32(rec + 100) == PATH_RC_FLAG_UNSHIFTABLE);
    CHECK(le_f64(rec + 104) == 0 && le_f64(rec + 112) == 1 && le_f64(rec + 120) == 0);
    CHECK(le_f64(rec + 128) == 11 && le_f64(rec + 136) == 12 && le_f64(rec + 144) == 13);
    CHECK(le_f64(rec + 152) == 14 && le_f64(rec + 160) == 15 && le_f64(rec + 168) == 16);
    CHECK(le_f64(rec + 176) == 17);
    CHECK(le_f64(rec + 184) == 18 && le_f64(rec + 192) == 19 && le_f64(rec + 200) == 20);
    CHECK(le_f64(rec + 208) == (double)luminance(rgb_make(18, 19, 20)));
    CHECK(le_f64(rec + 216 + 8 * 44) == 0.75);
}

/* Copies src to dst after applying `patch` bytes at `offset` (or truncating / appending). */
static const char *patched_copy(const char *src, const char *name, long offset, const void *patch, size_t n,
                                long truncate_to, int append)
{
    static unsigned char buf[1 << 16];
    const char *dst = test_tmp_path(name);
    FILE *f = fopen(src, "rb");
    size_t len;
    if (!f) return dst;
    len = fread(buf, 1, sizeof buf, f);
    fclose(f);
    if (patch) memcpy(buf + offset, patch, n);
    if (truncate_to >= 0) len = (size_t)truncate_to;
    f = fopen(dst, "wb");
    if (!f) return dst;
    fwrite(buf, 1, len, f);
    if (append) fputc(0, f);
    fclose(f);
    return dst;
}

TEST(reservoir_dump_rejects_malformed)
{
    enum { W = 3, H = 2 };
    reservoir rs[W * H], *back = NULL;
    reservoir_dump_info info, got;
    rerror e;
    char good[1024]; /* test_tmp_path's buffers rotate: keep a copy */
    unsigned char seven = 7, two = 2, zero4[4] = {0, 0, 0, 0};
    int i;
    struct {
        const char *name, *expect;
        long offset;
        const void *patch;
        size_t n;
        long truncate_to;
        int append;
    } cases[] = {
        {"bad-magic.bin", "magic", 0, "XXXXXXXX", 8, -1, 0},
        {"bad-version.bin", "version", 8, &seven, 1, -1, 0},
        {"bad-recsize.bin", "record size", 16, &seven, 1, -1, 0},
        {"bad-count.bin", "record count", 40, &seven, 1, -1, 0},
        {"bad-width.bin", "empty", 24, zero4, 4, -1, 0},
        {"short-header.bin", "shorter", 0, NULL, 0, 30, 0},
        {"truncated.bin", "bytes", 0, NULL, 0, 64 + 216 * 5 + 100, 0},
        {"extra.bin", "bytes", 0, NULL, 0, -1, 1},
        /* record 1 (offset 64 + 216): rc_k = 2 with length... set length to 2 and technique
         * NEE on a path whose lobes were written for a longer path */
        {"bad-record.bin", "record 1", 64 + 216 + 44, &two, 1, -1, 0},
    };
    snprintf(good, sizeof good, "%s", test_tmp_path("good-dump.bin"));
    for (i = 0; i < W * H; ++i) random_reservoir(&rs[i], (uint32_t)i + 1, NULL);
    memset(&info, 0, sizeof info);
    info.width = W;
    info.height = H;
    strcpy(info.tag, "test");
    /* record 1 must be a non-empty path longer than 2 for the bad-record case */
    rs[1].y.length = 5;
    memset(rs[1].y.lobe, PATH_LOBE_NONE, sizeof rs[1].y.lobe);
    for (i = 1; i < 5; ++i) rs[1].y.lobe[i] = 0;
    rs[1].y.technique = PATH_TECH_BSDF;
    rs[1].y.rc_k = PATH_RC_NONE;
    CHECKF(reservoir_dump_write(good, rs, &info, &e) == 0, "%s", e.msg);
    for (i = 0; i < (int)(sizeof cases / sizeof cases[0]); ++i) {
        const char *bad = patched_copy(good, cases[i].name, cases[i].offset, cases[i].patch, cases[i].n,
                                       cases[i].truncate_to, cases[i].append);
        CHECKF(reservoir_dump_read(bad, &back, &got, &e) != 0, "%s was accepted", cases[i].name);
        CHECK(back == NULL);
        CHECKF(strstr(e.msg, bad) == e.msg, "message does not start with the path: %s", e.msg);
        CHECKF(strstr(e.msg, cases[i].expect) != NULL, "%s: message '%s' lacks '%s'", cases[i].name, e.msg,
               cases[i].expect);
    }
    CHECK(reservoir_dump_read(test_tmp_path("no-such-dump.bin"), &back, &got, &e) != 0);
    /* writer: a tag without a terminator within 16 bytes is an error and leaves no file */
    memset(info.tag, 'x', sizeof info.tag);
    CHECK(reservoir_dump_write(test_tmp_path("long-tag.bin"), rs, &info, &e) != 0);
    CHECK(!test_file_exists(test_tmp_path("long-tag.bin")));
}
