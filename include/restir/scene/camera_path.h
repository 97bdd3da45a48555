/* Whether a camera pose, and every pose an animated camera interpolates, has a gluLookAt
 * basis (issue 27: keyframes whose interpolated `up` passes through zero rendered a black
 * image with exit 0). */
#ifndef RESTIR_CAMERA_PATH_H
#define RESTIR_CAMERA_PATH_H

#include "restir/scene/scene.h"

/* Largest |coordinate| of a vertex, a camera eye/target/up, an animation's translation or
 * pivot. Geometry is float and the ray-triangle test multiplies three coordinate
 * differences: (2e12)^3 = 8e36 stays below FLT_MAX = 3.4e38, (2e13)^3 does not. */
#define SCENE_COORD_MAX 1e12

enum camera_pose_problem { CAMERA_POSE_OK, CAMERA_POSE_EYE_IS_TARGET, CAMERA_POSE_UP_DEGENERATE };

/* The problem of one pose: eye = target, or up zero or parallel to the view direction (the
 * sine of the angle <= 1e-6). */
enum camera_pose_problem camera_pose_check(const camera_pose *pose);
/* "eye and target are the same point" / "up is zero or parallel to the view direction". */
const char *camera_pose_problem_text(enum camera_pose_problem p);

/* The first integer frame strictly between keyframes a and b (a.frame < b.frame) whose
 * interpolated pose (scene_camera_at's arithmetic) has a problem: returns the problem and
 * the frame in *frame, or CAMERA_POSE_OK. Every frame is checked when there are at most
 * 2^20 of them; above that 2^20 evenly spaced frames and every frame within one spacing
 * of the worst of them (a degenerate stretch is where the sine is smallest). */
enum camera_pose_problem camera_segment_check(const camera_keyframe *a, const camera_keyframe *b, int *frame);

#endif
