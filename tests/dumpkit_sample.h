/* Private to tests: the GPU record (tools/dumpkit/restir_dump.h, restir_gpu_record) that
 * tests/test_dumpkit.c converts in C and tests/dumpkit_cuda_roundtrip.cu through nvcc:
 * a BSDF path of d = 4 reconnecting at k = 3, lobes 0xFF, 1, 2, 0, then none. */
#ifndef RESTIR_TESTS_DUMPKIT_SAMPLE_H
#define RESTIR_TESTS_DUMPKIT_SAMPLE_H

#include <string.h>
#include "../tools/dumpkit/restir_dump.h"

static void dumpkit_sample_gpu_record(restir_gpu_record *g)
{
    memset(g, 0, sizeof *g);
    g->wsum = 0.75f;
    g->W = 3.0f;
    g->confidence = 5.0f;
    g->seed = 11;
    g->pixel = 222;
    g->sample = 3;
    g->packed_d_tech_k_npss = 4u | (RESTIR_TECH_BSDF << 8) | (3u << 16);
    g->packed_lobe[0] = 0xFFu | (1u << 8) | (2u << 16) | (0u << 24);
    g->packed_lobe[1] = g->packed_lobe[2] = g->packed_lobe[3] = 0xFFFFFFFFu;
    g->rc_triangle = 77;
    g->rc_position[2] = -1.5f;
    g->rc_normal[1] = 1.0f;
    g->rc_wo[0] = 1.0f;
    g->rc_pdf_prev = 0.5f;
    g->rc_geom = 0.25f;
    g->rc_pdf = 1.0f;
    g->F[0] = 0.125f;
    g->target = 0.25f;
}

#endif
