/* Motion vectors and disocclusion (issue 10): for every pixel, where its primary hit x1
 * was in the previous frame's image, and whether it was visible there.
 *
 * x1 lies on object o. Its rest-pose point is T_o(frame)^-1 x1 and its previous position
 * T_o(prev_frame) T_o(frame)^-1 x1 (rigid transforms, restir/scene/animation.h); projecting
 * that with the previous camera gives the previous image position, and the motion vector
 * is that minus the pixel's sample position. Visibility in the previous frame is judged
 * against the previous G-buffer, as real-time renderers do (no extra rays): the texel the
 * point lands in must show the same object, at the same depth and orientation. */
#include "restir/render/motion.h"

#include "restir/core/threads.h"
#include "restir/render/gbuffer.h"
#include "restir/scene/animation.h"

#include <math.h>

/* Defaults, measured against ray-traced ground truth on the animated test scenes
 * (tests/test_motion.c, docs/scenes.md): a relative tangent-plane distance of 5% of the view
 * depth accepts the sub-pixel offset between the point and the previous texel's own
 * (possibly jittered) sample on surfaces up to grazing angles, while an occluder in front
 * (a different object, or the same object much nearer) fails; a normal cosine of 0.9
 * (about 25 degrees) tolerates the rotation of a moving object between frames but not a
 * different face. */
void motion_thresholds_default(motion_thresholds *t)
{
    t->max_relative_depth = 0.05f;
    t->min_normal_cos = 0.9f;
}

/* A = T_prev T_cur^-1 = (M_p M_c^T, t_p - M_p M_c^T t_c) for rigid M. */
static void relative_transform(const scene *s, uint32_t object, int frame, int prev_frame, double a[3][3],
                               double t[3])
{
    double mc[3][3], tc[3], mp[3][3], tp[3];
    int i, j, k;
    scene_object_transform_at_d(s, object, frame, mc, tc);
    scene_object_transform_at_d(s, object, prev_frame, mp, tp);
    for (i = 0; i < 3; ++i)
        for (j = 0; j < 3; ++j) {
            a[i][j] = 0;
            for (k = 0; k < 3; ++k) a[i][j] += mp[i][k] * mc[j][k];
        }
    for (i = 0; i < 3; ++i) t[i] = tp[i] - (a[i][0] * tc[0] + a[i][1] * tc[1] + a[i][2] * tc[2]);
}

static vec3 apply(double a[3][3], const double t[3], vec3 p)
{
    return v3((real)(a[0][0] * p.x + a[0][1] * p.y + a[0][2] * p.z + t[0]),
              (real)(a[1][0] * p.x + a[1][1] * p.y + a[1][2] * p.z + t[1]),
              (real)(a[2][0] * p.x + a[2][1] * p.y + a[2][2] * p.z + t[2]));
}

vec3 motion_previous_position(const scene *s, uint32_t object, int frame, int prev_frame, vec3 p)
{
    double a[3][3], t[3];
    relative_transform(s, object, frame, prev_frame, a, t);
    return apply(a, t, p);
}

/* The previous-frame tests of one reprojected point (previous position xp, geometric normal
 * np, previous view depth depth) against the previous texel it lands in. */
static int previous_texel_agrees(const gbuffer_texel *pt, uint32_t object, vec3 xp, vec3 np, real depth,
                                 const motion_thresholds *th)
{
    vec3 d;
    if (!pt->valid || pt->hit.object != object) return 0;
    if (v3_dot(v3_from_f(pt->hit.ng), np) < th->min_normal_cos) return 0;
    d = v3_sub(v3_from_f(pt->hit.position), xp);
    return fabs((double)v3_dot(d, np)) <= (double)th->max_relative_depth * depth;
}

static void texel_motion(gbuffer_texel *t, const scene *s, int frame, const camera *prev_cam, int prev_frame,
                         const gbuffer *prev, const motion_thresholds *th, double a[3][3], double tr[3],
                         uint32_t *cached)
{
    double zero[3] = {0, 0, 0};
    vec3 xp, np;
    real px, py, depth;
    int ix, iy;
    t->motion[0] = t->motion[1] = 0;
    t->prev_valid = 0;
    if (!t->valid) return;
    if (*cached != t->hit.object) {
        relative_transform(s, t->hit.object, frame, prev_frame, a, tr);
        *cached = t->hit.object;
    }
    xp = apply(a, tr, v3_from_f(t->hit.position));
    np = v3_normalize(apply(a, zero, v3_from_f(t->hit.ng)));
    if (!camera_project(prev_cam, xp, &px, &py)) return;
    t->motion[0] = (float)(px - (real)t->pixel[0]);
    t->motion[1] = (float)(py - (real)t->pixel[1]);
    if (!(px >= 0 && py >= 0 && px < prev_cam->width && py < prev_cam->height)) return;
    /* The previous pixel exactly as gbuffer_previous_pixel finds it from the stored floats. */
    gbuffer_previous_pixel(t, &ix, &iy);
    if (ix < 0 || iy < 0 || ix >= prev->width || iy >= prev->height) return;
    depth = v3_dot(v3_sub(xp, prev_cam->eye), prev_cam->forward);
    t->prev_valid = previous_texel_agrees(gbuffer_at(prev, ix, iy), t->hit.object, xp, np, depth, th);
}

typedef struct {
    gbuffer *cur;
    const scene *s;
    int frame, prev_frame;
    const camera *prev_cam;
    const gbuffer *prev;
    const motion_thresholds *th;
} motion_job;

static void motion_tile(void *ctx, int x0, int y0, int x1, int y1, int worker)
{
    const motion_job *m = ctx;
    double a[3][3], tr[3];
    uint32_t cached = UINT32_MAX; /* per tile: the transform is a pure function of the object */
    int x, y;
    (void)worker;
    for (y = y0; y < y1; ++y)
        for (x = x0; x < x1; ++x)
            texel_motion(&m->cur->texels[(long)y * m->cur->width + x], m->s, m->frame, m->prev_cam, m->prev_frame,
                         m->prev, m->th, a, tr, &cached);
}

int gbuffer_motion(gbuffer *cur, const scene *s, int frame, const camera *prev_cam, int prev_frame,
                   const gbuffer *prev, const motion_thresholds *th, int threads, rerror *e)
{
    motion_thresholds defaults;
    motion_job m;
    if (!th) {
        motion_thresholds_default(&defaults);
        th = &defaults;
    }
    if (!prev || !prev->texels || prev->width != prev_cam->width || prev->height != prev_cam->height)
        return rerror_set(e, "gbuffer_motion: the previous G-buffer does not match the previous camera");
    m.cur = cur;
    m.s = s;
    m.frame = frame;
    m.prev_frame = prev_frame;
    m.prev_cam = prev_cam;
    m.prev = prev;
    m.th = th;
    parallel_tiles(cur->width, cur->height, 16, threads, motion_tile, &m, NULL, NULL);
    return 0;
}

int gbuffer_build_with_motion(gbuffer *g, const scene *s, int frame, uint32_t seed, int jitter, int threads, rerror *e)
{
    scene prev_s;
    gbuffer prev;
    camera pc, cc;
    int status;
    camera_init(&pc, scene_camera_at(s, frame - 1), s->width, s->height);
    camera_init(&cc, scene_camera_at(s, frame), s->width, s->height);
    if (scene_clone(&prev_s, s, e)) return -1;
    status = scene_pose_at(&prev_s, frame - 1, e);
    if (!status) status = gbuffer_build(&prev, &prev_s, &pc, seed, (uint32_t)(frame - 1), jitter, threads, e);
    scene_free(&prev_s);
    if (status) return -1;
    status = gbuffer_build(g, s, &cc, seed, (uint32_t)frame, jitter, threads, e);
    if (!status) status = gbuffer_motion(g, s, frame, &pc, frame - 1, &prev, NULL, threads, e);
    gbuffer_free(&prev);
    if (status) gbuffer_free(g);
    return status;
}

/* ---- dual motion vectors (Enhanced §6.4; Zeng et al. 2021; docs/correlation.md) --------- */

/* The rule, from Enhanced §6.4 ("an alternative motion vector that assumes consistent
 * relative motion between occluding and disoccluded surfaces"): a disoccluded pixel p
 * (sample position c_p) reprojects by its own motion to a previous texel o that shows the
 * occluder. The occluder's point there (sample position c_o in frame t-1) moves with its
 * object to frame t and projects to z_o: the occluder's screen motion is v = z_o - c_o.
 * Assuming p's surface kept its position RELATIVE to the occluder, p was at c_p - v in
 * frame t-1. The dual source pixel is the previous texel containing c_p - v; if that
 * texel still shows the occluder (the occluder's edge runs through it: the disoccluded
 * strip is only |v| wide, so this is common for motions of a pixel or two), the texel one
 * pixel further along -v (the step rounded to the pixel grid). It is accepted when it is
 * valid, shows p's object, and its geometric normal agrees with p's (carried to its
 * previous pose) within the disocclusion thresholds' normal cosine. No depth test: the
 * dual vector is an approximation that lands near, not on, p's point. The choice depends
 * on G-buffers alone, never on reservoirs, so temporal reuse from it stays unbiased. */

/* The previous texel containing (px, py), or NULL off screen. */
static const gbuffer_texel *previous_texel_at(const gbuffer *prev, real px, real py, int *x, int *y)
{
    if (!(px >= 0 && py >= 0 && px < (real)prev->width && py < (real)prev->height)) return NULL;
    *x = (int)floor((double)px);
    *y = (int)floor((double)py);
    return gbuffer_at(prev, *x, *y);
}

/* 1 if previous texel q can stand for t's surface (object and normal). */
static int dual_texel_accepted(const gbuffer_texel *q, const gbuffer_texel *t, const scene *s, int frame,
                               int prev_frame)
{
    motion_thresholds th;
    vec3 p0, p1, p2;
    if (!q || !q->valid || q->hit.object != t->hit.object) return 0;
    p0 = v3_from_f(t->hit.position);
    p1 = motion_previous_position(s, t->hit.object, frame, prev_frame, p0);
    p2 = motion_previous_position(s, t->hit.object, frame, prev_frame, v3_add(p0, v3_from_f(t->hit.ng)));
    motion_thresholds_default(&th);
    return v3_dot(v3_from_f(q->hit.ng), v3_normalize(v3_sub(p2, p1))) >= th.min_normal_cos;
}

int gbuffer_dual_previous_pixel(const gbuffer_texel *t, const scene *s, int frame, const camera *cam, int prev_frame,
                                const gbuffer *prev, int *x, int *y)
{
    const gbuffer_texel *o, *q;
    vec3 zo;
    real zx, zy, vx, vy, dx, dy, len;
    int ox, oy;
    if (!t->valid || t->prev_valid) return 0;
    gbuffer_previous_pixel(t, &ox, &oy);
    if (ox < 0 || oy < 0 || ox >= prev->width || oy >= prev->height) return 0;
    o = gbuffer_at(prev, ox, oy);
    if (!o->valid || o->hit.object == t->hit.object) return 0; /* not an occluder: nothing to follow */
    zo = motion_previous_position(s, o->hit.object, prev_frame, frame, v3_from_f(o->hit.position));
    if (!camera_project(cam, zo, &zx, &zy)) return 0;
    vx = zx - (real)o->pixel[0]; /* the occluder's screen motion t-1 -> t */
    vy = zy - (real)o->pixel[1];
    dx = (real)t->pixel[0] - vx;
    dy = (real)t->pixel[1] - vy;
    q = previous_texel_at(prev, dx, dy, x, y);
    if (q && q->valid && q->hit.object == o->hit.object) {
        len = (real)sqrt((double)(vx * vx + vy * vy));
        if (!(len > 0)) return 0;
        q = previous_texel_at(prev, dx - vx / len, dy - vy / len, x, y);
    }
    return dual_texel_accepted(q, t, s, frame, prev_frame);
}
