/* sequence_util.h: real-time sequences for the tests. */
#include "sequence_util.h"

#include <string.h>
#include "test.h"

int rt_sequence_runs(const scene *s, const restir_options *o, int first, int last, int runs, restir_frame_sink sink,
                     void *user, restir_stats *run0)
{
    restir_sequence seq;
    rerror e;
    int k;
    memset(&seq, 0, sizeof seq);
    seq.first = first;
    seq.last = last;
    for (k = 0; k < runs; ++k) {
        restir_options ok = *o;
        restir_stats total;
        ok.seed = o->seed + 7919u * (uint32_t)k;
        if (restir_render_sequence(s, &ok, &seq, sink, user, &total, &e)) {
            test_fail(__FILE__, __LINE__, "restir_render_sequence: %s", e.msg);
            return -1;
        }
        if (k == 0 && run0) *run0 = total;
    }
    return 0;
}

typedef struct {
    int first, count;
    image *img;
} image_copies;

static int copy_frame(void *user, int frame, const image *img, const restir_stats *st, rerror *e)
{
    image_copies *c = user;
    image *dst;
    (void)st;
    if (frame < c->first || frame >= c->first + c->count) return 0;
    dst = &c->img[frame - c->first];
    if (image_alloc(dst, img->width, img->height, e)) return -1;
    memcpy(dst->px, img->px, sizeof(float) * 3 * (size_t)img->width * (size_t)img->height);
    return 0;
}

int rt_sequence_images(const scene *s, const restir_options *o, int first, int last, image *img)
{
    image_copies c;
    int i;
    c.first = first;
    c.count = last - first + 1;
    c.img = img;
    memset(img, 0, sizeof *img * (size_t)c.count);
    if (rt_sequence_runs(s, o, first, last, 1, copy_frame, &c, NULL) == 0) return 0; /* run 0: o->seed */
    for (i = 0; i < c.count; ++i) image_free(&img[i]);
    return -1;
}

