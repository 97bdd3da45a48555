// Compiled by nvcc in tests/test_dumpkit.c (dumpkit_cuda_round_trip): the CUDA view of the
// dump records (tools/dumpkit/restir_dump.cuh) reads a record the oracle encoded, and writes
// one the oracle then decodes. Usage: dumpkit_cuda_roundtrip IN.rec OUT.rec (216 bytes each).
// The kernel is compiled (device pass) but not launched: no GPU is needed.
#include <cstdio>
#include <cstring>
#include "../tools/dumpkit/restir_dump.cuh"
#include "dumpkit_sample.h"

__global__ void restir_write_empty(restir_resv_record *out, restir_gpu_record *gpu)
{
    restir_resv_record_empty(&out[threadIdx.x], 1.0, 0u);
    restir_gpu_record_to_resv(&gpu[threadIdx.x], &out[threadIdx.x]);
}

int main(int argc, char **argv)
{
    restir_resv_record rec;
    restir_gpu_record g;
    FILE *in, *out;
    if (argc != 3 || !(in = std::fopen(argv[1], "rb"))) return 2;
    if (std::fread(&rec, sizeof rec, 1, in) != 1) return 2;
    std::fclose(in);
    // what the oracle wrote, field by field (tests/test_dumpkit.c filled_reservoir)
    std::printf("seed %u pixel %u sample %u length %u technique %u rc_k %u lobe1 %u rc_triangle %u confidence %g\n",
                rec.seed, rec.pixel, rec.sample, rec.length, rec.technique, rec.rc_k, rec.lobe[1], rec.rc_triangle,
                rec.confidence);
    // a GPU record in binary32 with packed bytes (tests/dumpkit_sample.h), converted on the host
    dumpkit_sample_gpu_record(&g);
    restir_gpu_record_to_resv(&g, &rec);
    if (!(out = std::fopen(argv[2], "wb")) || std::fwrite(&rec, sizeof rec, 1, out) != 1) return 2;
    return std::fclose(out) == 0 ? 0 : 2;
}
