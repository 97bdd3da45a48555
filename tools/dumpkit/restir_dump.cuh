// The restir stage-dump records for CUDA (docs/formats.md "Reservoir dump"). CUDA has doubles
// and 8-bit types, so a kernel writes the 216-byte .resv record itself: restir_resv_record of
// restir_dump.h, whose every field sits at its natural alignment (no padding in the device
// ABI either: checked below at compile time, for host and device passes alike). Copy the
// records back (cudaMemcpy) and write them after a restir_resv_header, unchanged on a
// little-endian host. A kernel that keeps binary32 can write restir_gpu_record instead and
// convert with restir_gpu_record_to_resv (also __host__ __device__ here).
//
// tests/test_dumpkit.c compiles tests/dumpkit_cuda_roundtrip.cu with nvcc when it is present
// (/usr/local/cuda/bin/nvcc or on PATH; no GPU is needed: the round trip runs on the host)
// and skips otherwise.
#ifndef RESTIR_DUMP_CUH
#define RESTIR_DUMP_CUH

#include <cstddef>
#include "restir_dump.h"

static_assert(sizeof(restir_resv_record) == 216, "restir_resv_record must be 216 bytes");
static_assert(sizeof(restir_resv_header) == 64, "restir_resv_header must be 64 bytes");
static_assert(sizeof(restir_gpu_record) == 144, "restir_gpu_record must be 144 bytes");
static_assert(offsetof(restir_resv_record, length) == 44 && offsetof(restir_resv_record, lobe) == 48 &&
                  offsetof(restir_resv_record, rc_triangle) == 64 && offsetof(restir_resv_record, rc_flags) == 100 &&
                  offsetof(restir_resv_record, rc_wo) == 104 && offsetof(restir_resv_record, light_pdf) == 176 &&
                  offsetof(restir_resv_record, F) == 184 && offsetof(restir_resv_record, target) == 208,
              "restir_resv_record offsets differ from docs/formats.md");

// An empty reservoir as docs/formats.md "Empty records" has it.
__host__ __device__ inline void restir_resv_record_empty(restir_resv_record *r, double confidence, uint32_t n_invalid)
{
    unsigned char *b = reinterpret_cast<unsigned char *>(r);
    for (unsigned i = 0; i < sizeof *r; ++i) b[i] = 0;
    for (int i = 0; i < 16; ++i) r->lobe[i] = RESTIR_LOBE_NONE;
    r->confidence = confidence;
    r->n_invalid = n_invalid;
}

#endif
