/* Pinhole camera. */
#include "restir/render/camera.h"

void camera_init(camera *c, camera_pose pose, int width, int height)
{
    c->eye = pose.eye;
    c->forward = v3_normalize(v3_sub(pose.target, pose.eye));
    c->right = v3_normalize(v3_cross(c->forward, pose.up));
    c->up = v3_cross(c->right, c->forward);
    c->tan_half_fov_y = tan(pose.fov_y_degrees * PI_R / 360);
    c->aspect = (real)width / (real)height;
    c->width = width;
    c->height = height;
}

ray camera_ray(const camera *c, real px, real py)
{
    ray r;
    real sx = (2 * px / c->width - 1) * c->tan_half_fov_y * c->aspect;
    real sy = (1 - 2 * py / c->height) * c->tan_half_fov_y;
    vec3 d = v3_normalize(v3_add(c->forward, v3_add(v3_scale(c->right, sx), v3_scale(c->up, sy))));
    r.origin = v3f_from(c->eye);
    r.dir = v3f_from(d);
    r.tmin = 0;
    r.tmax = INFINITY;
    return r;
}

int camera_project(const camera *c, vec3 p, real *px, real *py)
{
    vec3 d = v3_sub(p, c->eye);
    real z = v3_dot(d, c->forward), sx, sy;
    if (z <= 0) return 0;
    sx = v3_dot(d, c->right) / (z * c->tan_half_fov_y * c->aspect);
    sy = v3_dot(d, c->up) / (z * c->tan_half_fov_y);
    *px = (sx + 1) * c->width / 2;
    *py = (1 - sy) * c->height / 2;
    return 1;
}
