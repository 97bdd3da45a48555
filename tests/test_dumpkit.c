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
#include "dumpkit_sample.h"
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

/* The size in bytes of an HLSL field type of restir_dump.hlsl (0: unknown). */
static int hlsl_size(const char *type)
{
    if (!strcmp(type, "float") || !strcmp(type, "uint")) return 4;
    if (!strcmp(type, "float2")) return 8;
    if (!strcmp(type, "float3")) return 12;
    if (!strcmp(type, "uint4")) return 16;
    return 0;
}

/* No HLSL compiler is installed: the "@ OFFSET" comments of RestirGpuRecord in
 * tools/dumpkit/restir_dump.hlsl are checked against offsetof() of the C mirror
 * restir_gpu_record, and the fields must tile its 144 bytes without gaps. */
TEST(dumpkit_hlsl_offsets_match_c)
{
    static const struct {
        const char *name;
        size_t offset;
    } c_fields[] = {
        {"wsum", offsetof(restir_gpu_record, wsum)}, {"W", offsetof(restir_gpu_record, W)},
        {"confidence", offsetof(restir_gpu_record, confidence)}, {"n_invalid", offsetof(restir_gpu_record, n_invalid)},
        {"seed", offsetof(restir_gpu_record, seed)}, {"pixel", offsetof(restir_gpu_record, pixel)},
        {"sample", offsetof(restir_gpu_record, sample)},
        {"packed_d_tech_k_npss", offsetof(restir_gpu_record, packed_d_tech_k_npss)},
        {"packed_lobe", offsetof(restir_gpu_record, packed_lobe)}, {"rc_triangle", offsetof(restir_gpu_record, rc_triangle)},
        {"rc_bary", offsetof(restir_gpu_record, rc_bary)}, {"rc_position", offsetof(restir_gpu_record, rc_position)},
        {"rc_normal", offsetof(restir_gpu_record, rc_normal)}, {"rc_flags", offsetof(restir_gpu_record, rc_flags)},
        {"rc_wo", offsetof(restir_gpu_record, rc_wo)}, {"rc_pdf_prev", offsetof(restir_gpu_record, rc_pdf_prev)},
        {"rc_geom", offsetof(restir_gpu_record, rc_geom)}, {"rc_pdf", offsetof(restir_gpu_record, rc_pdf)},
        {"rc_radiance", offsetof(restir_gpu_record, rc_radiance)}, {"light_pdf", offsetof(restir_gpu_record, light_pdf)},
        {"F", offsetof(restir_gpu_record, F)}, {"target", offsetof(restir_gpu_record, target)},
    };
    const size_t n_fields = sizeof c_fields / sizeof c_fields[0];
    char line[512], type[32], name[64];
    FILE *fp = fopen("tools/dumpkit/restir_dump.hlsl", "r");
    int in_struct = 0, seen = 0, next = 0;
    size_t i;
    CHECKF(fp != NULL, "tools/dumpkit/restir_dump.hlsl: cannot open (run from the repository root)");
    if (!fp) return;
    while (fgets(line, sizeof line, fp)) {
        const char *at = strstr(line, "// @ ");
        int offset;
        if (strstr(line, "struct RestirGpuRecord")) in_struct = 1;
        if (!in_struct) continue;
        if (strstr(line, "};")) break;
        if (!at || sscanf(line, " %31s %63[A-Za-z0-9_];", type, name) != 2 || sscanf(at, "// @ %d", &offset) != 1)
            continue;
        for (i = 0; i < n_fields && strcmp(c_fields[i].name, name); ++i) {}
        CHECKF(i < n_fields, "HLSL field %s has no C counterpart in restir_gpu_record", name);
        if (i < n_fields)
            CHECKF((size_t)offset == c_fields[i].offset, "%s: HLSL says @ %d, offsetof in C is %lu", name, offset,
                   (unsigned long)c_fields[i].offset);
        CHECKF(offset == next && hlsl_size(type) > 0, "%s %s @ %d: expected @ %d (fields must tile the record)", type,
               name, offset, next);
        next = offset + hlsl_size(type);
        seen++;
    }
    fclose(fp);
    CHECKF((size_t)seen == n_fields && next == 144 && sizeof(restir_gpu_record) == 144,
           "%d HLSL fields ending at byte %d; the C mirror has %lu fields in %lu bytes", seen, next,
           (unsigned long)n_fields, (unsigned long)sizeof(restir_gpu_record));
}

/* A GPU record (binary32, packed bytes) converted on the host is a .resv record the oracle
 * decodes field for field. */
TEST(dumpkit_gpu_record_converts)
{
    restir_gpu_record g;
    restir_resv_record rec;
    reservoir back;
    real pss[PATH_MAX_PSS];
    unsigned char buf[RESERVOIR_DUMP_RECORD_PSS];
    rerror e;
    dumpkit_sample_gpu_record(&g);
    restir_gpu_record_to_resv(&g, &rec);
    if (!little_endian()) return;
    memcpy(buf, &rec, sizeof rec);
    reservoir_record_decode(buf, 0, &back, pss);
    CHECK(back.wsum == (real)0.75 && back.W == (real)3 && back.confidence == (real)5 && back.y.seed == 11 &&
          back.y.pixel == 222 && back.y.sample == 3);
    CHECK(back.y.length == 4 && back.y.technique == PATH_TECH_BSDF && back.y.rc_k == 3 && back.y.lobe[0] == PATH_LOBE_NONE &&
          back.y.lobe[1] == 1 && back.y.lobe[2] == 2 && back.y.lobe[3] == 0 && back.y.lobe[4] == PATH_LOBE_NONE);
    CHECK(back.y.rc_triangle == 77 && back.y.rc_position.z == -1.5f && back.y.rc_pdf_prev == (real)0.5 && back.y.rc_geom == (real)0.25 &&
          back.y.F.r == (real)0.125 && back.y.target == (real)0.25);
    CHECKF(path_sample_check(&back.y, "converted record", &e) == 0, "%s", e.msg);
}

/* The CUDA view (tools/dumpkit/restir_dump.cuh) compiled by nvcc reads a record the oracle
 * encoded and writes one the oracle decodes (no GPU needed; skipped without nvcc; long:
 * nvcc takes seconds). */
TEST_LONG(dumpkit_cuda_round_trip)
{
    static char out[8192];
    char cmd[4000], in_path[1100], out_path[1100], exe[1100];
    const char *nvcc = system("/usr/local/cuda/bin/nvcc --version >/dev/null 2>&1") == 0 ? "/usr/local/cuda/bin/nvcc"
                       : system("nvcc --version >/dev/null 2>&1") == 0                   ? "nvcc"
                                                                                        : NULL;
    unsigned char buf[RESERVOIR_DUMP_RECORD_PSS];
    reservoir r, back;
    real pss[PATH_MAX_PSS], pss_back[PATH_MAX_PSS];
    FILE *fp;
    if (!nvcc) {
        printf("    (skipped: no nvcc)\n");
        return;
    }
    snprintf(exe, sizeof exe, "%s/dumpkit_cuda", test_tmpdir());
    snprintf(in_path, sizeof in_path, "%s/cuda_in.rec", test_tmpdir());
    snprintf(out_path, sizeof out_path, "%s/cuda_out.rec", test_tmpdir());
    snprintf(cmd, sizeof cmd, "%s -std=c++14 -o %s tests/dumpkit_cuda_roundtrip.cu > %s.log 2>&1", nvcc, exe, exe);
    CHECKF(system(cmd) == 0, "nvcc failed: %s (log %s.log)", cmd, exe);
    if (test_has_failed()) return;
    filled_reservoir(&r, pss);
    reservoir_record_encode(&r, 0, buf);
    fp = fopen(in_path, "wb");
    CHECK(fp && fwrite(buf, 1, RESERVOIR_DUMP_RECORD_BASE, fp) == RESERVOIR_DUMP_RECORD_BASE);
    if (fp) fclose(fp);
    snprintf(cmd, sizeof cmd, "%s %s %s", exe, in_path, out_path);
    fp = popen(cmd, "r");
    out[0] = '\0';
    if (fp) {
        size_t n = fread(out, 1, sizeof out - 1, fp);
        out[n] = '\0';
        CHECKF(pclose(fp) == 0, "%s failed:\n%s", cmd, out);
    }
    CHECKF(strstr(out, "seed 7 pixel 1234 sample 56 length 3 technique 1 rc_k 2 lobe1 1 rc_triangle 99 confidence 21"),
           "the CUDA struct read other values:\n%s", out);
    fp = fopen(out_path, "rb");
    CHECK(fp && fread(buf, 1, RESERVOIR_DUMP_RECORD_BASE, fp) == RESERVOIR_DUMP_RECORD_BASE);
    if (fp) fclose(fp);
    reservoir_record_decode(buf, 0, &back, pss_back);
    CHECK(back.W == (real)3 && back.y.seed == 11 && back.y.pixel == 222 && back.y.length == 4 &&
          back.y.technique == PATH_TECH_BSDF && back.y.rc_k == 3 && back.y.lobe[2] == 2 && back.y.rc_triangle == 77 &&
          back.y.rc_position.z == -1.5f && back.y.target == (real)0.25);
}
