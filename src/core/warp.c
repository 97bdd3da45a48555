/* Sampling warps and their inverses (PBRT 4th ed. §A.5 gives the forward maps;
 * the inverses are derived case by case below). */
#include "restir/core/warp.h"

static real clamp01(real x) { return x < 0 ? 0 : (x > 1 ? 1 : x); }

static real wrap_angle01(real phi) /* phi in (-pi, pi] -> [0, 1) */
{
    real u = phi / (2 * PI_R);
    if (u < 0) u += 1;
    return u >= 1 ? 0 : u;
}

/* Inverse of the concentric map. In the left/right wedges (|x| > |y|) the forward
 * map used r = a, phi = (pi/4) b/a with |phi| < pi/4, so a = sign(x) R and
 * phi = atan(y/x). In the top/bottom wedges r = b, phi = pi/2 - (pi/4) a/b with
 * phi in [pi/4, 3pi/4], so b = sign(y) R and phi = atan2(y/b, x/b). */
vec2 warp_disk_concentric_inverse(vec2 p)
{
    real R = sqrt(p.x * p.x + p.y * p.y), a, b;
    if (R == 0) return v2((real)0.5, (real)0.5);
    if (fabs(p.x) > fabs(p.y)) {
        a = p.x > 0 ? R : -R;
        b = a * atan(p.y / p.x) * (4 / PI_R);
    } else {
        real phi;
        b = p.y > 0 ? R : -R;
        phi = atan2(p.y / b, p.x / b);
        a = (PI_R / 2 - phi) * (4 / PI_R) * b;
    }
    return v2(clamp01((a + 1) / 2), clamp01((b + 1) / 2));
}

real warp_disk_pdf(void) { return INV_PI_R; }

vec2 warp_cosine_hemisphere_inverse(vec3 w) { return warp_disk_concentric_inverse(v2(w.x, w.y)); }

real warp_cosine_hemisphere_pdf(real cos_theta) { return cos_theta > 0 ? cos_theta * INV_PI_R : 0; }

static vec3 from_z_phi(real z, real phi)
{
    real r2 = 1 - z * z, r = r2 > 0 ? sqrt(r2) : 0;
    return v3(r * cos(phi), r * sin(phi), z);
}

vec3 warp_uniform_sphere(vec2 u) { return from_z_phi(1 - 2 * u.x, 2 * PI_R * u.y); }

vec2 warp_uniform_sphere_inverse(vec3 w) { return v2(clamp01((1 - w.z) / 2), wrap_angle01(atan2(w.y, w.x))); }

real warp_uniform_sphere_pdf(void) { return 1 / (4 * PI_R); }

vec3 warp_uniform_hemisphere(vec2 u) { return from_z_phi(u.x, 2 * PI_R * u.y); }

vec2 warp_uniform_hemisphere_inverse(vec3 w) { return v2(clamp01(w.z), wrap_angle01(atan2(w.y, w.x))); }

real warp_uniform_hemisphere_pdf(void) { return 1 / (2 * PI_R); }

vec3 warp_uniform_cone(vec2 u, real cos_max)
{
    return from_z_phi((1 - u.x) + u.x * cos_max, 2 * PI_R * u.y);
}

vec2 warp_uniform_cone_inverse(vec3 w, real cos_max)
{
    return v2(clamp01((1 - w.z) / (1 - cos_max)), wrap_angle01(atan2(w.y, w.x)));
}

real warp_uniform_cone_pdf(real cos_max) { return 1 / (2 * PI_R * (1 - cos_max)); }

vec2 warp_uniform_triangle_inverse(vec2 b)
{
    real s = 1 - b.x;
    return v2(clamp01(s * s), s > 0 ? clamp01(b.y / s) : 0);
}
