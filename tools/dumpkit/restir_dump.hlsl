// What an HLSL pass writes for a restir stage dump (docs/formats.md "Reservoir dump"; the C
// mirror and the host conversion are restir_gpu_record / restir_gpu_record_to_resv in
// restir_dump.h).
//
// HLSL has no 8-bit types and doubles are an optional feature, so a shader does not write the
// 216-byte .resv record. It writes RestirGpuRecord: 36 little-endian 32-bit words, 144 bytes,
// into a RWStructuredBuffer<RestirGpuRecord> (structured buffers pack 4-byte scalars and
// float2/float3 without padding) or, word by word, into a RWByteAddressBuffer at 144 * index.
// Every real is binary32; length, technique, rc_k and n_pss share one word and lobe[16] four
// words, in the byte order of the .resv record (byte j of word w is byte 4w + j). The host
// reads the buffer back, converts each record with restir_gpu_record_to_resv (binary32 to
// binary64 is exact), and writes the 64-byte .resv header and the records (restir_dump.h,
// restir_resv_header; or tools/dumpkit/restir_dump.py).
//
// No HLSL compiler (dxc, fxc, slangc) is installed where this kit is tested: this file is
// not compiled here. tests/test_dumpkit.c parses the "@ OFFSET" comments below and checks
// each against offsetof() of the C mirror, and checks that the fields tile the 144 bytes.
// The field meanings, empty records and conventions (W = wsum / target after every stage,
// lobe codes, confidence, Rec. 709 target) are those of docs/formats.md.

#ifndef RESTIR_DUMP_HLSL
#define RESTIR_DUMP_HLSL

#define RESTIR_TECH_NONE 0u
#define RESTIR_TECH_NEE 1u
#define RESTIR_TECH_BSDF 2u
#define RESTIR_LOBE_NEE 0xFEu
#define RESTIR_LOBE_NONE 0xFFu
#define RESTIR_RC_FLAG_UNSHIFTABLE 1u
#define RESTIR_RC_FLAG_DISTANT 2u
#define RESTIR_GPU_RECORD_BYTES 144u

struct RestirGpuRecord
{
    float wsum;                   // @ 0   sum of the streamed resampling weights
    float W;                      // @ 4   unbiased contribution weight = wsum / target (0 if empty)
    float confidence;             // @ 8   c
    uint n_invalid;               // @ 12  weights skipped as NaN, infinite or negative
    uint seed;                    // @ 16  replay identity: run seed,
    uint pixel;                   // @ 20  pixel index y * width + x that traced the path,
    uint sample;                  // @ 24  sample index (docs/rng.md)
    uint packed_d_tech_k_npss;    // @ 28  length | technique << 8 | rc_k << 16 | n_pss << 24
    uint4 packed_lobe;            // @ 32  lobe[4i + j] in byte j of component i; 0xFF none, 0xFE NEE
    uint rc_triangle;             // @ 48  x_k's triangle (0xFFFFFFFE: x_k at infinity)
    float2 rc_bary;               // @ 52  (b1, b2)
    float3 rc_position;           // @ 60  x_k, or its unit direction at infinity
    float3 rc_normal;             // @ 72  geometric normal at x_k
    uint rc_flags;                // @ 84  RESTIR_RC_FLAG_*
    float3 rc_wo;                 // @ 88  omega_k (0 when k = d)
    float rc_pdf_prev;            // @ 100 p_{k-1}(omega_{k-1}), lobe selection included
    float rc_geom;                // @ 104 G(x_{k-1} -> x_k)
    float rc_pdf;                 // @ 108 p_k(omega_k); 1 when k = d or omega_k is the NEE direction
    float3 rc_radiance;           // @ 112 suffix radiance L_k
    float light_pdf;              // @ 124 NEE solid-angle pdf of x_d from x_{d-1}
    float3 F;                     // @ 128 PSS path contribution f/p, RGB
    float target;                 // @ 140 0.2126 F.r + 0.7152 F.g + 0.0722 F.b
};

uint RestirPackBytes(uint b0, uint b1, uint b2, uint b3)
{
    return (b0 & 0xFFu) | ((b1 & 0xFFu) << 8) | ((b2 & 0xFFu) << 16) | ((b3 & 0xFFu) << 24);
}

// An empty reservoir as docs/formats.md "Empty records" has it: only confidence and
// n_invalid may be non-zero, every lobe is 0xFF.
RestirGpuRecord RestirGpuRecordEmpty(float confidence, uint n_invalid)
{
    RestirGpuRecord r = (RestirGpuRecord)0;
    r.confidence = confidence;
    r.n_invalid = n_invalid;
    r.packed_lobe = uint4(0xFFFFFFFFu, 0xFFFFFFFFu, 0xFFFFFFFFu, 0xFFFFFFFFu);
    return r;
}

// Through a byte-address buffer: the same 36 words at RESTIR_GPU_RECORD_BYTES * index.
void RestirStoreGpuRecord(RWByteAddressBuffer buffer, uint index, RestirGpuRecord r)
{
    uint a = RESTIR_GPU_RECORD_BYTES * index;
    buffer.Store4(a + 0, uint4(asuint(r.wsum), asuint(r.W), asuint(r.confidence), r.n_invalid));
    buffer.Store4(a + 16, uint4(r.seed, r.pixel, r.sample, r.packed_d_tech_k_npss));
    buffer.Store4(a + 32, r.packed_lobe);
    buffer.Store4(a + 48, uint4(r.rc_triangle, asuint(r.rc_bary), asuint(r.rc_position.x)));
    buffer.Store4(a + 64, uint4(asuint(r.rc_position.yz), asuint(r.rc_normal.xy)));
    buffer.Store4(a + 80, uint4(asuint(r.rc_normal.z), r.rc_flags, asuint(r.rc_wo.xy)));
    buffer.Store4(a + 96, uint4(asuint(r.rc_wo.z), asuint(r.rc_pdf_prev), asuint(r.rc_geom), asuint(r.rc_pdf)));
    buffer.Store4(a + 112, uint4(asuint(r.rc_radiance), asuint(r.light_pdf)));
    buffer.Store4(a + 128, uint4(asuint(r.F), asuint(r.target)));
}

#endif
