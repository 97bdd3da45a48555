/* The restir stage-dump records as C structs, for a GPU build that writes its passes in our
 * format (docs/formats.md "Reservoir dump", "G-buffer dump"; docs/oracle.md §1 step 4).
 * Standalone: <stdint.h> only, no part of the restir library. Compiles warning-free as C99
 * (gcc, clang: -Wall -Wextra -Wpedantic) and as C++11 (g++); CUDA code includes it through
 * restir_dump.cuh (compiled by nvcc in tests/test_dumpkit.c when nvcc is present). HLSL has
 * no 8-bit types and doubles are an optional GPU feature: a shader writes restir_gpu_record
 * (below; restir_dump.hlsl) and the host converts it.
 *
 * The structs mirror the bytes of the files exactly: every field sits at its natural
 * alignment, so there is no padding, and the compile-time checks below fail on an ABI that
 * would add some. The files are LITTLE-ENDIAN: on a little-endian host (x86, ARM as usually
 * run) a record is written with fwrite(&rec, sizeof rec, 1, f); elsewhere swap
 * the bytes of every field first. Every `real` of the oracle is stored as binary64 (double)
 * whatever the precision of the build; geometry fields are binary32.
 *
 * Copying from a GPU buffer: convert float W, F, ... to double when filling the struct (a
 * binary32 value converts to binary64 exactly). What each field means, the empty-record
 * contents and the conventions a GPU build must copy: docs/formats.md. The round trip
 * through the oracle's own encoder and decoder is checked by tests/test_dumpkit.c. */
#ifndef RESTIR_DUMPKIT_H
#define RESTIR_DUMPKIT_H

#include <stdint.h>

#define RESTIR_RESV_MAGIC "RSTRRESV"     /* 8 bytes, no terminator */
#define RESTIR_GBUF_MAGIC "RSTRGBUF"
#define RESTIR_RESV_FLAG_PSS 1u          /* records carry restir_resv_pss after the record */
#define RESTIR_RESV_MAX_PSS 45
#define RESTIR_LOBE_NEE 0xFEu            /* lobe[d-1] of an NEE-sampled last vertex */
#define RESTIR_LOBE_NONE 0xFFu           /* not a scattering vertex */
#define RESTIR_TECH_NONE 0u              /* empty sample */
#define RESTIR_TECH_NEE 1u
#define RESTIR_TECH_BSDF 2u
#define RESTIR_RC_FLAG_UNSHIFTABLE 1u

/* .resv header, 64 bytes. record_size = 216, or 216 + 8 * 45 = 576 with RESTIR_RESV_FLAG_PSS. */
typedef struct {
    char magic[8];          /* "RSTRRESV" */
    uint32_t version;       /* 1 */
    uint32_t header_size;   /* 64 */
    uint32_t record_size;   /* 216 or 576 */
    uint32_t flags;         /* RESTIR_RESV_FLAG_PSS iff some record has n_pss > 0 */
    uint32_t width, height; /* the image, or the --dump-region rectangle */
    uint32_t frame;
    uint32_t real_bits;     /* 64 or 32: the writer's precision (informational) */
    uint64_t count;         /* width * height */
    char tag[16];           /* stage name, printable ASCII, NUL-padded */
} restir_resv_header;

/* One reservoir with its selected path sample, 216 bytes (docs/formats.md "Record"). */
typedef struct {
    double wsum;            /*   0: sum of the streamed resampling weights */
    double W;               /*   8: unbiased contribution weight, = wsum / target after every stage */
    double confidence;      /*  16: c */
    uint32_t n_invalid;     /*  24: weights skipped as NaN, infinite or negative */
    uint32_t reserved;      /*  28: 0 */
    uint32_t seed;          /*  32: replay identity of the path tree ... */
    uint32_t pixel;         /*  36: ... pixel index y * width + x that traced it ... */
    uint32_t sample;        /*  40: ... and its sample index */
    uint8_t length;         /*  44: d, 2..16; 0 = empty */
    uint8_t technique;      /*  45: RESTIR_TECH_* */
    uint8_t rc_k;           /*  46: reconnection index k, 2..d; 0 = none */
    uint8_t n_pss;          /*  47: valid entries of the primary-sample vector */
    uint8_t lobe[16];       /*  48: lobe[j] = l_j, 1 <= j <= d-1; RESTIR_LOBE_NEE / _NONE */
    uint32_t rc_triangle;   /*  64: x_k's triangle (fields 64..175 only when rc_k != 0) */
    float rc_bary[2];       /*  68: (b1, b2) */
    float rc_position[3];   /*  76: x_k */
    float rc_normal[3];     /*  88: geometric normal at x_k, unit */
    uint32_t rc_flags;      /* 100: RESTIR_RC_FLAG_* */
    double rc_wo[3];        /* 104: omega_k (0 when k = d) */
    double rc_pdf_prev;     /* 128: p_{k-1}(omega_{k-1}), lobe selection included */
    double rc_geom;         /* 136: G(x_{k-1} -> x_k) */
    double rc_pdf;          /* 144: p_k(omega_k); 1 when k = d or omega_k is the NEE direction */
    double rc_radiance[3];  /* 152: suffix radiance L_k */
    double light_pdf;       /* 176: NEE solid-angle pdf of x_d from x_{d-1} */
    double F[3];            /* 184: PSS path contribution f/p, RGB */
    double target;          /* 208: p^ = 0.2126 R + 0.7152 G + 0.0722 B of F */
} restir_resv_record;

/* With RESTIR_RESV_FLAG_PSS each record is followed by these 360 bytes: pss[i] for
 * i < n_pss replaces the RNG_BSDF number of vertex 1 + i/3, slot i%3; the rest are 0. */
typedef struct {
    double pss[RESTIR_RESV_MAX_PSS];
} restir_resv_pss;

/* .gbuf header, 32 bytes, then width * height restir_gbuf_texel. */
typedef struct {
    char magic[8];        /* "RSTRGBUF" */
    uint32_t version;     /* 1 */
    uint32_t header_size; /* 32 */
    uint32_t record_size; /* 108 */
    uint32_t width, height, frame;
} restir_gbuf_header;

typedef struct {
    uint32_t valid;       /*   0: 0 if the primary ray missed */
    uint32_t triangle;    /*   4 */
    uint32_t material;    /*   8: index into the scene's material table (scene.h scene.materials) */
    uint32_t object;      /*  12: index into the scene's object names (scene.h scene.object_names) */
    float b1, b2, t;      /*  16: barycentrics of v1, v2; ray parameter */
    float position[3];    /*  28: x1 */
    float ng[3];          /*  40: geometric normal, front face (v1-v0)x(v2-v0) */
    float ns[3];          /*  52: shading normal */
    float view_dir[3];    /*  64: unit, x0 -> x1 */
    float distance;       /*  76: |x1 - x0| */
    float cos_theta;      /*  80: |cos| between the primary ray and ng */
    float depth;          /*  84: view-space depth */
    float pixel[2];       /*  88: sample position, continuous pixel coordinates */
    float motion[2];      /*  96: previous position minus sample position (pixels) */
    uint32_t prev_valid;  /* 104: 1 if x1 was visible in the previous frame */
} restir_gbuf_texel;

/* ---- what a shader writes: restir_gpu_record (restir_dump.hlsl, restir_dump.cuh) ---------
 * A GPU pass cannot write the .resv record directly from HLSL (no 8-bit types; doubles are
 * an optional feature), so it writes this record of 36 little-endian 32-bit words, 144
 * bytes: every real as binary32, the four byte fields of offsets 44..47 packed into one
 * word and lobe[16] into four, in the byte order of the .resv record (byte j of word w is
 * byte 4w + j). The host converts each record with restir_gpu_record_to_resv (binary32 ->
 * binary64 is exact), then writes the .resv header and records. restir_dump.hlsl declares
 * the same layout; tests/test_dumpkit.c checks its offsets against this struct. */
typedef struct {
    float wsum;             /*   0 */
    float W;                /*   4 */
    float confidence;       /*   8 */
    uint32_t n_invalid;     /*  12 */
    uint32_t seed;          /*  16 */
    uint32_t pixel;         /*  20 */
    uint32_t sample;        /*  24 */
    uint32_t packed_d_tech_k_npss; /* 28: length | technique << 8 | rc_k << 16 | n_pss << 24 */
    uint32_t packed_lobe[4];       /* 32: lobe[4i + j] in byte j of word i */
    uint32_t rc_triangle;   /*  48 */
    float rc_bary[2];       /*  52 */
    float rc_position[3];   /*  60 */
    float rc_normal[3];     /*  72 */
    uint32_t rc_flags;      /*  84 */
    float rc_wo[3];         /*  88 */
    float rc_pdf_prev;      /* 100 */
    float rc_geom;          /* 104 */
    float rc_pdf;           /* 108 */
    float rc_radiance[3];   /* 112 */
    float light_pdf;        /* 124 */
    float F[3];             /* 128 */
    float target;           /* 140 */
} restir_gpu_record;

#ifdef __CUDACC__
#define RESTIR_DUMPKIT_HD __host__ __device__
#else
#define RESTIR_DUMPKIT_HD
#endif

/* The .resv record of a GPU record (every binary32 converted exactly; reserved = 0). */
static RESTIR_DUMPKIT_HD inline void restir_gpu_record_to_resv(const restir_gpu_record *g, restir_resv_record *r)
{
    int i;
    r->wsum = g->wsum;
    r->W = g->W;
    r->confidence = g->confidence;
    r->n_invalid = g->n_invalid;
    r->reserved = 0;
    r->seed = g->seed;
    r->pixel = g->pixel;
    r->sample = g->sample;
    r->length = (uint8_t)(g->packed_d_tech_k_npss & 0xFFu);
    r->technique = (uint8_t)((g->packed_d_tech_k_npss >> 8) & 0xFFu);
    r->rc_k = (uint8_t)((g->packed_d_tech_k_npss >> 16) & 0xFFu);
    r->n_pss = (uint8_t)(g->packed_d_tech_k_npss >> 24);
    for (i = 0; i < 16; ++i) r->lobe[i] = (uint8_t)((g->packed_lobe[i / 4] >> (8 * (i % 4))) & 0xFFu);
    r->rc_triangle = g->rc_triangle;
    for (i = 0; i < 2; ++i) r->rc_bary[i] = g->rc_bary[i];
    for (i = 0; i < 3; ++i) {
        r->rc_position[i] = g->rc_position[i];
        r->rc_normal[i] = g->rc_normal[i];
        r->rc_wo[i] = g->rc_wo[i];
        r->rc_radiance[i] = g->rc_radiance[i];
        r->F[i] = g->F[i];
    }
    r->rc_flags = g->rc_flags;
    r->rc_pdf_prev = g->rc_pdf_prev;
    r->rc_geom = g->rc_geom;
    r->rc_pdf = g->rc_pdf;
    r->light_pdf = g->light_pdf;
    r->target = g->target;
}

/* Compile-time layout checks (a negative array size fails the build). */
typedef char restir_dumpkit_check_header[sizeof(restir_resv_header) == 64 ? 1 : -1];
typedef char restir_dumpkit_check_record[sizeof(restir_resv_record) == 216 ? 1 : -1];
typedef char restir_dumpkit_check_pss[sizeof(restir_resv_pss) == 360 ? 1 : -1];
typedef char restir_dumpkit_check_gbuf_header[sizeof(restir_gbuf_header) == 32 ? 1 : -1];
typedef char restir_dumpkit_check_gbuf_texel[sizeof(restir_gbuf_texel) == 108 ? 1 : -1];
typedef char restir_dumpkit_check_gpu_record[sizeof(restir_gpu_record) == 144 ? 1 : -1];

#endif
