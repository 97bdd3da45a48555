/* Camera poses without a basis (camera_path.h). */
#include "restir/scene/camera_path.h"

#include <math.h>
#include <string.h>

/* The sine of the angle between up and the view direction (0 when either is zero), and
 * whether eye and target coincide; in double, as the scene file's check always did. */
static double up_sine(const camera_pose *pose, int *same_point)
{
    double f[3], c[3], lf, lu, lc;
    f[0] = (double)pose->target.x - pose->eye.x;
    f[1] = (double)pose->target.y - pose->eye.y;
    f[2] = (double)pose->target.z - pose->eye.z;
    c[0] = f[1] * pose->up.z - f[2] * pose->up.y;
    c[1] = f[2] * pose->up.x - f[0] * pose->up.z;
    c[2] = f[0] * pose->up.y - f[1] * pose->up.x;
    lf = sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]);
    lu = sqrt((double)pose->up.x * pose->up.x + (double)pose->up.y * pose->up.y + (double)pose->up.z * pose->up.z);
    lc = sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
    *same_point = !(lf > 0);
    return lf > 0 && lu > 0 ? lc / (lf * lu) : 0;
}

enum camera_pose_problem camera_pose_check(const camera_pose *pose)
{
    int same;
    double s = up_sine(pose, &same);
    if (same) return CAMERA_POSE_EYE_IS_TARGET;
    return s > 1e-6 ? CAMERA_POSE_OK : CAMERA_POSE_UP_DEGENERATE;
}

const char *camera_pose_problem_text(enum camera_pose_problem p)
{
    return p == CAMERA_POSE_EYE_IS_TARGET ? "eye and target are the same point"
           : p == CAMERA_POSE_UP_DEGENERATE ? "up is zero or parallel to the view direction"
                                             : "ok";
}

/* The pose scene_camera_at gives at frame f for the two keyframes alone. */
static camera_pose pose_at(const camera_keyframe *a, const camera_keyframe *b, long f)
{
    camera_keyframe k[2];
    scene s;
    memset(&s, 0, sizeof s);
    k[0] = *a;
    k[1] = *b;
    s.keyframes = k;
    s.keyframe_count = 2;
    return scene_camera_at(&s, (int)f);
}

static enum camera_pose_problem check_frames(const camera_keyframe *a, const camera_keyframe *b, long lo, long hi,
                                             int *frame)
{
    long f;
    for (f = lo; f <= hi; ++f) {
        camera_pose p = pose_at(a, b, f);
        enum camera_pose_problem r = camera_pose_check(&p);
        if (r != CAMERA_POSE_OK) {
            *frame = (int)f;
            return r;
        }
    }
    return CAMERA_POSE_OK;
}

enum camera_pose_problem camera_segment_check(const camera_keyframe *a, const camera_keyframe *b, int *frame)
{
    const long samples = 1L << 20;
    long lo = (long)a->frame + 1, hi = (long)b->frame - 1, n = hi - lo + 1, i, worst = lo;
    double worst_sine = HUGE_VAL, step;
    if (n <= 0) return CAMERA_POSE_OK;
    if (n <= samples) return check_frames(a, b, lo, hi, frame);
    step = (double)(n - 1) / (double)(samples - 1);
    for (i = 0; i < samples; ++i) {
        long f = lo + (long)((double)i * step);
        camera_pose p = pose_at(a, b, f);
        int same;
        double s = up_sine(&p, &same);
        if (same) s = -1;
        if (s < worst_sine) worst_sine = s, worst = f;
    }
    lo = worst - (long)step - 1 > lo ? worst - (long)step - 1 : lo;
    hi = worst + (long)step + 1 < hi ? worst + (long)step + 1 : hi;
    return check_frames(a, b, lo, hi, frame);
}
