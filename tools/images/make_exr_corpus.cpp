// EXR evidence for docs/images.md: NOT part of the build (make never compiles it; the
// project does not depend on OpenEXR). Needs Debian's libopenexr-dev (OpenEXR 3.1) and a
// built librestir.a (for exr_write / exr_read / float_to_half). Build and run:
//
//   make -j2   # build/librestir.a
//   g++ -O2 -std=c++17 -Iinclude -Itests tools/images/make_exr_corpus.cpp build/librestir.a \
//       $(pkg-config --cflags --libs OpenEXR) -lm -lpthread -o /tmp/make_exr_corpus
//   /tmp/make_exr_corpus corpus tests/data/images   # the committed EXR corpus (values: tests/image_corpus.h)
//   /tmp/make_exr_corpus oracle /tmp/exr-oracle     # our writer's files, read back by libOpenEXR
//   /tmp/make_exr_corpus halfcheck                  # float_to_half == Imath::half(float), every float
//   /tmp/make_exr_corpus bench /tmp/exr-bench 7      # 1920x1080 half ZIP and PIZ: our decode time
//   /tmp/make_exr_corpus dump FILE...               # libOpenEXR's half RGBA of other writers' files
//   sh tools/images/make_exr_others.sh /tmp/make_exr_corpus /tmp/png-src tests/data/images
//
// The corpus files are written by libOpenEXR from the values of tests/image_corpus.h
// (the data-window coordinates of each pixel), so the test recomputes what each pixel
// must be. The refused kinds (tiled, multi-part, lossy compressions) are written too.
#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfMultiPartOutputFile.h>
#include <ImfOutputFile.h>
#include <ImfOutputPart.h>
#include <ImfPartType.h>
#include <ImfRgbaFile.h>
#include <ImfTiledOutputFile.h>
#include <ImfThreading.h>
#include <half.h>
#include <time.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

extern "C" {
#include "image_corpus.h"
#include "restir/core/exr.h"
}

using namespace Imf;
using Imath::Box2i;
using Imath::V2i;

struct Chan {
    const char *name;
    PixelType type;
    int c;         // value channel of image_corpus.h
    int ramp = 0;  // 1: corpus_ramp_half (the 16-bit wavelet file)
};

static int tame = 0; // the "tame" argument of image_corpus.h: set while writing PIZ files

static size_t type_size(PixelType t) { return t == HALF ? 2 : 4; }

// One buffer per channel holding the corpus values of the data window.
struct Planes {
    std::vector<std::vector<char>> buf;
    FrameBuffer fb;
    Planes(const Box2i &dw, const std::vector<Chan> &chans)
    {
        int w = dw.max.x - dw.min.x + 1, h = dw.max.y - dw.min.y + 1;
        buf.resize(chans.size());
        for (size_t k = 0; k < chans.size(); ++k) {
            size_t s = type_size(chans[k].type);
            buf[k].resize((size_t)w * h * s);
            for (int y = dw.min.y; y <= dw.max.y; ++y)
                for (int x = dw.min.x; x <= dw.max.x; ++x) {
                    char *p = &buf[k][((size_t)(y - dw.min.y) * w + (x - dw.min.x)) * s];
                    if (chans[k].type == HALF) {
                        uint16_t v = chans[k].ramp ? corpus_ramp_half(x, y, chans[k].c) : corpus_half(x, y, chans[k].c, tame);
                        memcpy(p, &v, 2);
                    } else {
                        uint32_t v = chans[k].type == FLOAT ? corpus_float(x, y, chans[k].c, tame) : corpus_uint(x, y, chans[k].c, tame);
                        memcpy(p, &v, 4);
                    }
                }
            char *origin = &buf[k][0] - ((ptrdiff_t)dw.min.x + (ptrdiff_t)dw.min.y * w) * (ptrdiff_t)s;
            fb.insert(chans[k].name, Slice(chans[k].type, origin, s, s * w));
        }
    }
};

static Header make_header(const Box2i &display, const Box2i &data, Compression comp, LineOrder order,
                          const std::vector<Chan> &chans)
{
    Header h(display, data, 1.0f, Imath::V2f(0, 0), 1.0f, order, comp);
    for (const Chan &c : chans) h.channels().insert(c.name, Channel(c.type));
    return h;
}

static void scanline(const std::string &path, Box2i display, Box2i data, Compression comp, LineOrder order,
                     const std::vector<Chan> &chans)
{
    Header h = make_header(display, data, comp, order, chans);
    tame = comp == PIZ_COMPRESSION;
    Planes p(data, chans);
    OutputFile out(path.c_str(), h);
    out.setFrameBuffer(p.fb);
    out.writePixels(data.max.y - data.min.y + 1);
    printf("wrote %s\n", path.c_str());
}

static Box2i box(int w, int h) { return Box2i(V2i(0, 0), V2i(w - 1, h - 1)); }

static void corpus(const std::string &dir)
{
    const struct {
        Compression c;
        const char *name;
    } comps[] = {{NO_COMPRESSION, "none"}, {RLE_COMPRESSION, "rle"}, {ZIPS_COMPRESSION, "zips"},
                 {ZIP_COMPRESSION, "zip"}, {PIZ_COMPRESSION, "piz"}};
    std::vector<Chan> rgba_half = {{"A", HALF, 3}, {"B", HALF, 2}, {"G", HALF, 1}, {"R", HALF, 0}};
    std::vector<Chan> rgba_float = {{"A", FLOAT, 3}, {"B", FLOAT, 2}, {"G", FLOAT, 1}, {"R", FLOAT, 0}};
    std::vector<Chan> rgb_uint = {{"B", UINT, 2}, {"G", UINT, 1}, {"R", UINT, 0}};
    std::vector<Chan> y_half = {{"Y", HALF, 0}};
    // R half, G float, B uint and a channel the reader skips (Z, float)
    std::vector<Chan> mixed = {{"B", UINT, 2}, {"G", FLOAT, 1}, {"R", HALF, 0}, {"Z", FLOAT, 3}};
    // 7 x 37: odd sizes and 3 ZIP chunks. PIZ files are 39 x 37 (2 chunks, odd sizes for
    // the wavelet's odd row and column): PIZ stores a bitmap of the words present, so a
    // narrower file would not compress and its chunks would be stored raw.
    for (auto &c : comps) {
        bool piz = c.c == PIZ_COMPRESSION;
        Box2i b = piz ? box(39, 37) : box(7, 37);
        scanline(dir + "/oe_" + c.name + "_half_rgba.exr", b, b, c.c, INCREASING_Y, rgba_half);
        scanline(dir + "/oe_" + c.name + "_float_rgba.exr", b, b, c.c, INCREASING_Y, rgba_float);
        scanline(dir + "/oe_" + c.name + "_uint_rgb.exr", piz ? b : box(5, 3), piz ? b : box(5, 3), c.c, INCREASING_Y, rgb_uint);
        scanline(dir + "/oe_" + c.name + "_half_y.exr", piz ? b : box(6, 4), piz ? b : box(6, 4), c.c, INCREASING_Y, y_half);
        scanline(dir + "/oe_" + c.name + "_mixed.exr", piz ? box(39, 35) : box(9, 35), piz ? box(39, 35) : box(9, 35), c.c, INCREASING_Y, mixed);
    }
    scanline(dir + "/oe_zip_decreasing.exr", box(7, 37), box(7, 37), ZIP_COMPRESSION, DECREASING_Y, rgba_half);
    scanline(dir + "/oe_piz_decreasing.exr", box(39, 37), box(39, 37), PIZ_COMPRESSION, DECREASING_Y, rgba_float);
    // data window partly outside the display window (0,0)-(9,14)
    scanline(dir + "/oe_piz_window.exr", box(10, 15), Box2i(V2i(-2, 3), V2i(8, 20)), PIZ_COMPRESSION, INCREASING_Y,
             rgba_half);
    scanline(dir + "/oe_zip_window.exr", box(10, 15), Box2i(V2i(4, -6), V2i(12, 9)), ZIP_COMPRESSION, INCREASING_Y,
             rgba_float);
    // more than 2^14 distinct values in a chunk: PIZ's 16-bit (modular) wavelet
    scanline(dir + "/oe_piz_wav16.exr", box(256, 33), box(256, 33), PIZ_COMPRESSION, INCREASING_Y,
             {{"B", HALF, 2, 1}, {"G", HALF, 1, 1}, {"R", HALF, 0, 1}});
    // refused by name
    const struct {
        Compression c;
        const char *name;
    } lossy[] = {{PXR24_COMPRESSION, "pxr24"}, {B44_COMPRESSION, "b44"}, {B44A_COMPRESSION, "b44a"},
                 {DWAA_COMPRESSION, "dwaa"}, {DWAB_COMPRESSION, "dwab"}};
    for (auto &c : lossy)
        scanline(dir + "/refused_" + c.name + ".exr", box(4, 3), box(4, 3), c.c, INCREASING_Y, rgba_half);
    {
        Header h = make_header(box(8, 8), box(8, 8), ZIP_COMPRESSION, INCREASING_Y, rgba_half);
        h.setTileDescription(TileDescription(4, 4, ONE_LEVEL));
        Planes p(box(8, 8), rgba_half);
        TiledOutputFile out((dir + "/refused_tiled.exr").c_str(), h);
        out.setFrameBuffer(p.fb);
        out.writeTiles(0, out.numXTiles() - 1, 0, out.numYTiles() - 1);
        printf("wrote %s/refused_tiled.exr\n", dir.c_str());
    }
    {
        std::vector<Header> hs(2, make_header(box(4, 3), box(4, 3), ZIP_COMPRESSION, INCREASING_Y, rgba_half));
        hs[0].setName("left");
        hs[1].setName("right");
        for (Header &h : hs) h.setType(SCANLINEIMAGE);
        MultiPartOutputFile out((dir + "/refused_multipart.exr").c_str(), hs.data(), 2);
        for (int i = 0; i < 2; ++i) {
            Planes p(box(4, 3), rgba_half);
            OutputPart part(out, i);
            part.setFrameBuffer(p.fb);
            part.writePixels(3);
        }
        printf("wrote %s/refused_multipart.exr\n", dir.c_str());
    }
}

// Reads `path` with libOpenEXR into HALF or FLOAT slices and compares every bit with `want`.
static int read_back(const std::string &path, int w, int h, PixelType t, const std::vector<uint32_t> &want)
{
    InputFile in(path.c_str());
    Box2i dw = in.header().dataWindow();
    if (dw != box(w, h)) {
        printf("%s: data window differs\n", path.c_str());
        return 1;
    }
    size_t s = type_size(t);
    std::vector<char> planes[3];
    FrameBuffer fb;
    const char *names[3] = {"R", "G", "B"};
    for (int c = 0; c < 3; ++c) {
        planes[c].resize((size_t)w * h * s);
        fb.insert(names[c], Slice(t, &planes[c][0], s, s * w));
    }
    in.setFrameBuffer(fb);
    in.readPixels(0, h - 1);
    int bad = 0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (int c = 0; c < 3; ++c) {
                uint32_t v = 0;
                memcpy(&v, &planes[c][((size_t)y * w + x) * s], s);
                if (v != want[((size_t)y * w + x) * 3 + c] && bad++ < 5)
                    printf("%s: (%d,%d) channel %d: 0x%x, expected 0x%x\n", path.c_str(), x, y, c, v,
                           want[((size_t)y * w + x) * 3 + c]);
            }
    printf("%s: %s (%s, %s, %d x %d) read by libOpenEXR: %d of %d values differ\n", path.c_str(),
           bad ? "FAIL" : "ok", t == HALF ? "half" : "float",
           in.header().compression() == ZIP_COMPRESSION ? "ZIP" : "NONE", w, h, bad, w * h * 3);
    return bad != 0;
}

// Our writer (exr_write) -> libOpenEXR reader, float and half, NONE and ZIP.
static int oracle(const std::string &dir)
{
    const int w = 37, h = 23;
    int fails = 0;
    image img;
    rerror e;
    if (image_alloc(&img, w, h, &e)) return 1;
    for (int t = 0; t < 2; ++t) {
        std::vector<uint32_t> want((size_t)w * h * 3);
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x)
                for (int c = 0; c < 3; ++c) {
                    float f;
                    uint32_t bits = t ? corpus_half(x, y, c, 0) : corpus_float(x, y, c, 0);
                    if (t) f = half_to_float((uint16_t)bits);
                    else memcpy(&f, &bits, 4);
                    image_pixel(&img, x, y)[c] = f;
                    want[((size_t)y * w + x) * 3 + c] = bits;
                }
        for (int comp : {EXR_NONE, EXR_ZIP}) {
            std::string path = dir + "/ours_" + (comp == EXR_ZIP ? "zip" : "none") + (t ? "_half" : "_float") + ".exr";
            if (exr_write(path.c_str(), &img, comp, t ? EXR_HALF : EXR_FLOAT, &e)) {
                printf("%s\n", e.msg);
                return 1;
            }
            fails += read_back(path, w, h, t ? HALF : FLOAT, want);
        }
    }
    image_free(&img);
    return fails;
}

// Every float through float_to_half and Imath::half: the same bits (NaN: both NaN).
static int halfcheck()
{
    unsigned long long bad = 0;
    uint32_t i = 0;
    do {
        float f;
        memcpy(&f, &i, 4);
        half ref(f);
        uint16_t ours = float_to_half(f), theirs = ref.bits();
        bool both_nan = (ours & 0x7c00) == 0x7c00 && (ours & 0x3ff) && (theirs & 0x7c00) == 0x7c00 && (theirs & 0x3ff);
        if (ours != theirs && !both_nan && bad++ < 5) printf("0x%08x: ours 0x%04x, Imath 0x%04x\n", i, ours, theirs);
    } while (++i != 0);
    for (uint32_t hb = 0; hb < 65536; ++hb) {
        half ref;
        ref.setBits((uint16_t)hb);
        float a = half_to_float((uint16_t)hb), b = (float)ref;
        uint32_t ab, bb;
        memcpy(&ab, &a, 4);
        memcpy(&bb, &b, 4);
        if (ab != bb && bad++ < 10) printf("half 0x%04x: ours 0x%08x, Imath 0x%08x\n", hb, ab, bb);
    }
    printf("halfcheck: %llu differences (all 2^32 floats -> half, all 2^16 halves -> float)\n", bad);
    return bad != 0;
}

// 1920x1080 half RGB, a smooth gradient with mild noise (render-like), written by
// libOpenEXR with ZIP and PIZ; our exr_read timed `runs` times, median reported.
static int bench(const std::string &dir, int runs)
{
    const int w = 1920, h = 1080;
    std::vector<half> px[3];
    for (int c = 0; c < 3; ++c) {
        px[c].resize((size_t)w * h);
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                float noise = (float)(corpus_mix(corpus_key(x, y, c)) & 1023) / 1023.0f - 0.5f;
                px[c][(size_t)y * w + x] = half(0.5f + 0.4f * (float)x / w * (float)(c + 1) / 3.0f +
                                               0.3f * (float)y / h + 0.02f * noise);
            }
    }
    for (Compression comp : {ZIP_COMPRESSION, PIZ_COMPRESSION}) {
        std::string path = dir + (comp == ZIP_COMPRESSION ? "/bench_zip.exr" : "/bench_piz.exr");
        Header hd(w, h);
        hd.compression() = comp;
        const char *names[3] = {"R", "G", "B"};
        FrameBuffer fb;
        for (int c = 0; c < 3; ++c) {
            hd.channels().insert(names[c], Channel(HALF));
            fb.insert(names[c], Slice(HALF, (char *)px[c].data(), 2, 2 * w));
        }
        {
            OutputFile out(path.c_str(), hd);
            out.setFrameBuffer(fb);
            out.writePixels(h);
        }
        std::vector<double> ms, cpu, lib;
        setGlobalThreadCount(0); // libOpenEXR single-threaded, like our reader
        for (int r = 0; r < runs; ++r) {
            fimage img;
            rerror e;
            struct timespec c0, c1;
            clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &c0);
            auto t0 = std::chrono::steady_clock::now();
            if (exr_read(path.c_str(), &img, &e)) {
                printf("%s\n", e.msg);
                return 1;
            }
            auto t1 = std::chrono::steady_clock::now();
            clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &c1);
            ms.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
            cpu.push_back((c1.tv_sec - c0.tv_sec) * 1e3 + (c1.tv_nsec - c0.tv_nsec) / 1e6);
            {
                // the reference: libOpenEXR decoding the same file into float slices
                std::vector<float> f[3];
                FrameBuffer rb;
                for (int c = 0; c < 3; ++c) {
                    f[c].resize((size_t)w * h);
                    rb.insert(names[c], Slice(FLOAT, (char *)f[c].data(), 4, 4 * w));
                }
                clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &c0);
                InputFile in(path.c_str());
                in.setFrameBuffer(rb);
                in.readPixels(0, h - 1);
                clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &c1);
                lib.push_back((c1.tv_sec - c0.tv_sec) * 1e3 + (c1.tv_nsec - c0.tv_nsec) / 1e6);
            }
            size_t bad = 0;
            for (int c = 0; c < 3; ++c)
                for (size_t i = 0; i < (size_t)w * h; ++i)
                    if (img.px[i * 3 + c] != (float)px[c][i]) bad++;
            fimage_free(&img);
            if (bad) printf("%s: %zu values differ\n", path.c_str(), bad);
        }
        std::sort(ms.begin(), ms.end());
        std::sort(cpu.begin(), cpu.end());
        std::sort(lib.begin(), lib.end());
        FILE *f = fopen(path.c_str(), "rb");
        fseek(f, 0, SEEK_END);
        long size = ftell(f);
        fclose(f);
        printf("%s (%ld bytes): exr_read median %.1f ms wall (min %.1f, max %.1f), %.1f ms CPU (min %.1f); "
               "libOpenEXR 1 thread %.1f ms CPU (min %.1f); %d runs\n",
               path.c_str(), size, ms[ms.size() / 2], ms.front(), ms.back(), cpu[cpu.size() / 2], cpu.front(),
               lib[lib.size() / 2], lib.front(), runs);
    }
    return 0;
}

// Prints what libOpenEXR reads from each file, as RgbaInputFile gives it (display
// window, half R G B A): "file width height" then one line per pixel, hex half bits.
// The expected values of files written by another program (ImageMagick).
static int dump(int argc, char **argv)
{
    for (int i = 2; i < argc; ++i) {
        RgbaInputFile in(argv[i]);
        Box2i dw = in.dataWindow();
        int w = dw.max.x - dw.min.x + 1, h = dw.max.y - dw.min.y + 1;
        std::vector<Rgba> px((size_t)w * h);
        in.setFrameBuffer(px.data() - dw.min.x - (ptrdiff_t)dw.min.y * w, 1, w);
        in.readPixels(dw.min.y, dw.max.y);
        const char *base = strrchr(argv[i], '/');
        printf("%s %d %d\n", base ? base + 1 : argv[i], w, h);
        for (const Rgba &p : px) printf("%04x %04x %04x %04x\n", p.r.bits(), p.g.bits(), p.b.bits(), p.a.bits());
    }
    return 0;
}

int main(int argc, char **argv)
{
    std::string mode = argc > 1 ? argv[1] : "";
    try {
        if (mode == "corpus" && argc == 3) corpus(argv[2]);
        else if (mode == "oracle" && argc == 3) return oracle(argv[2]);
        else if (mode == "halfcheck") return halfcheck();
        else if (mode == "dump") return dump(argc, argv);
        else if (mode == "bench" && argc >= 3) return bench(argv[2], argc > 3 ? atoi(argv[3]) : 7);
        else {
            fprintf(stderr, "usage: make_exr_corpus corpus DIR | oracle DIR | halfcheck | bench DIR [RUNS]\n");
            return 2;
        }
    } catch (const std::exception &ex) {
        fprintf(stderr, "error: %s\n", ex.what());
        return 1;
    }
    return 0;
}
