// Compiled by nvcc in tests/test_dumpkit.c (dumpkit_cuda_round_trip): the CUDA view of the
// dump records (tools/dumpkit/restir_dump.cuh) reads a record the oracle encoded, and writes
// one the oracle then decodes. Usage: dumpkit_cuda_roundtrip IN.rec OUT.rec (216 bytes each).
// The kernel is compiled (device pass) but not launched: no GPU is needed.
#include <cstdio>
#include <cstring>
#include "../tools/dumpkit/restir_dump.cuh"

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
    // a GPU record in binary32 with packed bytes, converted on the host
    std::memset(&g, 0, sizeof g);
    g.wsum = 0.75f;
    g.W = 3.0f;
    g.confidence = 5.0f;
    g.seed = 11;
    g.pixel = 222;
    g.sample = 3;
    g.packed_d_tech_k_npss = 4u | (RESTIR_TECH_BSDF << 8) | (3u << 16);
    g.packed_lobe[0] = 0xFFu | (1u << 8) | (2u << 16) | (0u << 24);
    g.packed_lobe[1] = g.packed_lobe[2] = g.packed_lobe[3] = 0xFFFFFFFFu;
    g.rc_triangle = 77;
    g.rc_position[2] = -1.5f;
    g.rc_pdf_prev = 0.5f;
    g.rc_geom = 0.25f;
    g.rc_pdf = 1.0f;
    g.F[0] = 0.125f;
    g.target = 0.25f;
    restir_gpu_record_to_resv(&g, &rec);
    if (!(out = std::fopen(argv[2], "wb")) || std::fwrite(&rec, sizeof rec, 1, out) != 1) return 2;
    return std::fclose(out) == 0 ? 0 : 2;
}
