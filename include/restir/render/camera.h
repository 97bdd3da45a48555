/* Pinhole camera with the gluLookAt basis (docs/design.md, Conventions): forward f = normalize(target - eye),
 * right = normalize(f x up), true up = right x f. Pixel (x, y) has row 0 at the TOP of
 * the image; the primary ray of the pixel centre goes through (x + 0.5, y + 0.5). */
#ifndef RESTIR_CAMERA_H
#define RESTIR_CAMERA_H

#include "restir/scene/bvh.h"
#include "restir/scene/scene.h"

typedef struct {
    vec3 eye, forward, right, up;
    real tan_half_fov_y, aspect;
    int width, height;
} camera;

void camera_init(camera *c, camera_pose pose, int width, int height);
/* Ray through continuous image coordinates (px, py) in [0,width] x [0,height]. */
ray camera_ray(const camera *c, real px, real py);
/* Inverse: image coordinates of a world point; returns 0 if behind the camera. */
int camera_project(const camera *c, vec3 p, real *px, real *py);

#endif
