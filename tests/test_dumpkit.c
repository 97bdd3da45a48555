/* The dump kit of tools/dumpkit (docs/oracle.md §1 step 4): the C structs of restir_dump.h
 * hold exactly the bytes the oracle's encoder writes and its decoder reads (both ways, on a
 * little-endian host), and the stdlib-only Python reader/writer reads a whole stage dump and
 * writes every file back byte for byte, validating the manifest against
 * docs/dump-manifest.schema.json (skipped when python3 is absent). */
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "../tools/dumpkit/restir_dump.h"
#include "restir/oracle/stage_dump.h"
#include "restir/restir/reservoir_dump.h"
#include "test.h"

static int little_endian(void)
{
    const uint32_t one = 1;
    unsigned char b;
    memcpy(&b, &one, 1);
    return b == 1;
}

/* A reservoir with every field set to something distinct (a valid NEE sample, k = 2 of d = 3). */
static void filled_reservoir(reservoir *r, real *pss)
{
    path_sample *s = &r->y;
    int i;
    reservoir_init(r);
    path_sample_begin(s, 7, 1234, 56);
    s->length = 3;
    s->technique = PATH_TECH_NEE;
    s->rc_k = 2;
    s->n_pss = 4;
    s->lobe[1] = 1;
    s->lobe[2] = PATH_LOBE_NEE;
    s->rc_triangle = 99;
    s->rc_bary[0] = 0.25f;
    s->rc_bary[1] = 0.125f;
    s->rc_position = v3f(1.5f, -2.25f, 3.0f);
    s->rc_normal = v3f(0, 1, 0);
    s->rc_flags = PATH_RC_FLAG_UNSHIFTABLE;
    s->rc_wo = v3(0.6, 0, 0.8);
    s->rc_pdf_prev = 0.31;
    s->rc_geom = 0.052;
    s->rc_pdf = 1;
    s->rc_radiance = rgb_make(2, 3, 4);
    s->light_pdf = 0.7;
    path_sample_set_contribution(s, rgb_make(0.1, 0.2, 0.3));
    for (i = 0; i < PATH_MAX_PSS; ++i) pss[i] = i < s->n_pss ? (real)(0.1 * i + 0.05) : 0;
    s->pss = pss;
    r->wsum = 0.9;
    r->W = r->wsum / s->target;
    r->confidence = 21;
    r->n_invalid = 3;
}

TEST(dumpkit_c_structs_round_trip)
{
    unsigned char buf[RESERVOIR_DUMP_RECORD_PSS];
    restir_resv_record rec;
    restir_resv_pss pss_rec;
    reservoir r, back;
    real pss[PATH_MAX_PSS], pss_back[PATH_MAX_PSS];
    int i;
    CHECK(offsetof(restir_resv_record, rc_triangle) == 64 && offsetof(restir_resv_record, rc_wo) == 104 &&
          offsetof(restir_resv_record, target) == 208 && offsetof(restir_gbuf_texel, prev_valid) == 104 &&
          offsetof(restir_resv_header, count) == 40 && offsetof(restir_resv_header, tag) == 48);
    CHECK(sizeof rec == RESERVOIR_DUMP_RECORD_BASE && sizeof rec + sizeof pss_rec == RESERVOIR_DUMP_RECORD_PSS &&
          sizeof(restir_gbuf_texel) == GBUFFER_DUMP_RECORD_SIZE && sizeof(restir_gbuf_header) == GBUFFER_DUMP_HEADER_SIZE &&
          sizeof(restir_resv_header) == RESERVOIR_DUMP_HEADER_SIZE);
    if (!little_endian()) return; /* the structs are the bytes only on a little-endian host */
    /* oracle encoder -> struct */
    filled_reservoir(&r, pss);
    reservoir_record_encode(&r, RESERVOIR_DUMP_FLAG_PSS, buf);
    memcpy(&rec, buf, sizeof rec);
    memcpy(&pss_rec, buf + sizeof rec, sizeof pss_rec);
    CHECK(rec.wsum == (double)r.wsum && rec.W == (double)r.W && rec.confidence == 21 && rec.n_invalid == 3);
    CHECK(rec.seed == 7 && rec.pixel == 1234 && rec.sample == 56 && rec.length == 3 && rec.technique == RESTIR_TECH_NEE);
    CHECK(rec.rc_k == 2 && rec.n_pss == 4 && rec.lobe[1] == 1 && rec.lobe[2] == RESTIR_LOBE_NEE &&
          rec.lobe[0] == RESTIR_LOBE_NONE && rec.lobe[15] == RESTIR_LOBE_NONE);
    CHECK(rec.rc_triangle == 99 && rec.rc_bary[1] == 0.125f && rec.rc_position[1] == -2.25f && rec.rc_normal[1] == 1);
    CHECK(rec.rc_flags == RESTIR_RC_FLAG_UNSHIFTABLE && rec.rc_wo[2] == (double)(real)0.8 &&
          rec.rc_pdf_prev == (double)(real)0.31);
    CHECK(rec.rc_geom == (double)(real)0.052 && rec.rc_pdf == 1 && rec.rc_radiance[2] == 4 &&
          rec.light_pdf == (double)(real)0.7);
    CHECK(rec.F[1] == (double)(real)0.2 && rec.target == (double)r.y.target);
    CHECK(pss_rec.pss[3] == (double)pss[3] && pss_rec.pss[4] == 0);
    /* struct -> oracle decoder (a GPU build writing with the structs) */
    rec.W = 4.5;
    rec.rc_position[0] = -7.0f;
    rec.lobe[1] = 2;
    pss_rec.pss[0] = 0.5;
    memcpy(buf, &rec, sizeof rec);
    memcpy(buf + sizeof rec, &pss_rec, sizeof pss_rec);
    reservoir_record_decode(buf, RESERVOIR_DUMP_FLAG_PSS, &back, pss_back);
    CHECK(back.W == (real)4.5 && back.y.rc_position.x == -7.0f && back.y.lobe[1] == 2 && back.y.pss[0] == (real)0.5);
    for (i = 1; i < PATH_MAX_PSS; ++i) CHECK(back.y.pss[i] == pss[i]);
    CHECK(back.y.seed == 7 && back.y.rc_triangle == 99 && back.confidence == 21 && back.n_invalid == 3);
}

/* The Python kit reads and writes back every file of a stage dump byte for byte, and its
 * directory check agrees with the manifest (skipped without python3). */
TEST(dumpkit_python_round_trip)
{
    static char out[65536];
    char cmd[4000], dir[1100];
    int status;
    if (system("python3 -c 'import struct, json' >/dev/null 2>&1") != 0) {
        printf("    (skipped: no python3)\n");
        return;
    }
    snprintf(dir, sizeof dir, "%s/kitdump", test_tmpdir());
    CHECKF(test_cli(out, sizeof out,
                    "render scenes/pillars.scene --method restir --preset gris-realtime --size 24x16 --sequence 0..1 "
                    "--mutations 1 --mutation fp --quiet --no-png --threads 2 -o %s/kit.pfm --dump-dir %s",
                    test_tmpdir(), dir) == 0,
           "%s", out);
    snprintf(cmd, sizeof cmd, "python3 tools/dumpkit/restir_dump.py selftest %s > %s/selftest.txt 2>&1", dir,
             test_tmpdir());
    status = system(cmd);
    CHECKF(status == 0, "the Python kit did not read or write back a file of %s (%s/selftest.txt)", dir, test_tmpdir());
    /* the manifest is validated against docs/dump-manifest.schema.json: a word for the
       numeric mutate_after is refused */
    snprintf(cmd, sizeof cmd,
             "mkdir -p %s/badm && sed 's/\"mutate_after\": 2/\"mutate_after\": \"temporal\"/' %s/manifest.json > "
             "%s/badm/manifest.json && grep -q '\"mutate_after\": \"temporal\"' %s/badm/manifest.json && "
             "! python3 tools/dumpkit/restir_dump.py check %s/badm >/dev/null 2>&1",
             test_tmpdir(), dir, test_tmpdir(), test_tmpdir(), test_tmpdir());
    CHECKF(system(cmd) == 0, "the schema check accepted \"mutate_after\": \"temporal\" (%s)", cmd);
    /* and it refuses a cut-short file */
    snprintf(cmd, sizeof cmd,
             "cp %s/frame_0001/temporal.resv %s/short.resv && truncate -s -8 %s/short.resv && "
             "python3 tools/dumpkit/restir_dump.py show %s/short.resv >/dev/null 2>&1",
             dir, test_tmpdir(), test_tmpdir(), test_tmpdir());
    CHECKF(system(cmd) != 0, "the Python kit read a truncated file");
}
