/* Lights: alias table, power-proportional selection, uniform area sampling and the
 * solid-angle pdf (include/restir/scene/lights.h). */
#include <stdlib.h>
#include <string.h>
#include "restir/scene/lights.h"
#include "restir/core/rng.h"
#include "pt_util.h"
#include "test.h"

static real u_test(uint32_t pixel, uint32_t sample, uint32_t slot)
{
    return rng_u(rng_key_make(test_seed(), pixel, sample), RNG_TEST, 0, slot);
}

/* Vose's table reproduces its pmf: chi-square over the entries (zero weights never drawn). */
TEST(alias_table_frequencies)
{
    enum { N = 37, DRAWS = 400000 };
    real w[N];
    double observed[N], expected[N], chi2, p;
    alias_table t;
    rerror e;
    int i, dof;
    for (i = 0; i < N; ++i) {
        /* Spread over three decades, with a few zeros. */
        w[i] = (i % 7 == 3) ? 0 : (real)pow(10.0, 3.0 * u_test(1, (uint32_t)i, 0));
        observed[i] = 0;
    }
    CHECKF(alias_table_build(&t, w, N, &e) == 0, "%s", e.msg);
    for (i = 0; i < DRAWS; ++i) observed[alias_table_sample(&t, u_test(2, (uint32_t)i, 0), u_test(2, (uint32_t)i, 1))] += 1;
    for (i = 0; i < N; ++i) expected[i] = t.pmf[i] * DRAWS;
    p = chi2_test(observed, expected, N, &chi2, &dof);
    alias_table_free(&t);
    CHECKF(p > 1e-3, "chi2 = %g, dof = %d, p = %g", chi2, dof, p);
}

/* The exact probability that the table realises (summed over its columns) equals the pmf. */
TEST(alias_table_exact_mass)
{
    enum { N = 50 };
    real w[N], mass[N];
    alias_table t;
    rerror e;
    int i;
    for (i = 0; i < N; ++i) {
        w[i] = (real)(i % 5 == 0 ? 0 : 1 + i * i);
        mass[i] = 0;
    }
    CHECKF(alias_table_build(&t, w, N, &e) == 0, "%s", e.msg);
    for (i = 0; i < N; ++i) {
        mass[i] += t.threshold[i] / N;
        mass[t.alias[i]] += (1 - t.threshold[i]) / N;
    }
    for (i = 0; i < N; ++i) CHECK_NEAR(mass[i], t.pmf[i], 1e-6);
    alias_table_free(&t);
    /* Bad weights are errors, not crashes. */
    w[3] = -1;
    CHECK(alias_table_build(&t, w, N, &e) != 0);
    CHECK(strstr(e.msg, "weight 3") != NULL);
}

/* Four emitters of different radiance, area and orientation around the origin, plus one
 * non-emissive triangle and one zero-area emitter (which must be ignored). */
static int make_light_scene(scene *s)
{
    uint32_t grey, warm, dim, blue;
    if (test_scene_begin(s, 8, 4)) return -1;
    grey = test_scene_material(s, MAT_LAMBERT, rgb_gray((real)0.5), rgb_gray(0));
    warm = test_scene_material(s, MAT_LAMBERT, rgb_gray(0), rgb_make(17, 12, 4));
    dim = test_scene_material(s, MAT_LAMBERT, rgb_gray(0), rgb_gray(1));
    blue = test_scene_material(s, MAT_LAMBERT, rgb_gray(0), rgb_make(0, 0, 5));
    /* Above, facing down (towards the origin). */
    test_scene_triangle(s, v3f(-1, 2, -1), v3f(1, 2, -1), v3f(0, 2, 1), warm);
    /* To the +x side, facing -x. */
    test_scene_triangle(s, v3f(3, -1, -1), v3f(3, 1, -1), v3f(3, 0, 2), dim);
    test_scene_triangle(s, v3f(0, -2, 0), v3f(1, -2, 0), v3f(0, -2, 1), grey);
    /* Below, facing AWAY from the origin (back side seen). */
    test_scene_triangle(s, v3f(-2, -3, -2), v3f(2, -3, -2), v3f(0, -3, 2), blue);
    /* Behind, large and dim, facing +z towards the origin. */
    test_scene_triangle(s, v3f(-4, -4, -5), v3f(4, -4, -5), v3f(0, 4, -5), dim);
    /* Degenerate emitter. */
    test_scene_triangle(s, v3f(5, 5, 5), v3f(5, 5, 5), v3f(6, 6, 6), warm);
    return 0;
}

TEST(lights_build_from_emissive_triangles)
{
    scene s;
    light_set ls;
    rerror e;
    size_t i;
    real sum = 0;
    CHECK(make_light_scene(&s) == 0);
    CHECKF(lights_build(&ls, &s, &e) == 0, "%s", e.msg);
    CHECK(ls.count == 4);
    CHECK(ls.light_of_triangle[2] == LIGHT_NONE);
    CHECK(ls.light_of_triangle[5] == LIGHT_NONE);
    CHECK(ls.light_of_triangle[0] == 0 && ls.light_of_triangle[4] == 3);
    CHECK(light_pdf_area(&ls, 2) == 0 && light_select_pdf(&ls, 5) == 0);
    /* Front normal of the first light points down, its area is 2. */
    CHECK_NEAR(ls.lights[0].normal.y, -1, 1e-6);
    CHECK_NEAR(ls.lights[0].area, 2, 1e-6);
    for (i = 0; i < ls.count; ++i) {
        real power = luminance(ls.lights[i].emission) * ls.lights[i].area;
        CHECK_NEAR(ls.select.pmf[i], power / ls.total_power, 1e-12);
        sum += ls.select.pmf[i];
    }
    CHECK_NEAR(sum, 1, 1e-12);
    lights_free(&ls);
    scene_free(&s);
}

/* Which of the n^2 congruent sub-triangles (barycentric grid) contains (b0, b1). */
static int barycentric_cell(vec2 b, int n)
{
    real a = b.x * n, c = b.y * n;
    int i = (int)a, j = (int)c, upper;
    if (i >= n) i = n - 1;
    if (j >= n) j = n - 1;
    upper = (a - i) + (c - j) >= 1;
    return (i * n + j) * 2 + upper;
}

static int barycentric_cell_valid(int cell, int n)
{
    int upper = cell & 1, i = (cell >> 1) / n, j = (cell >> 1) % n;
    return upper ? i + j <= n - 2 : i + j <= n - 1;
}

/* Light sampling against its pdf: a chi-square over (light, barycentric sub-triangle)
 * cells. Each of the n^2 sub-triangles has area/n^2, so the expected frequency of a cell
 * is P(l)/n^2 = pdf_area · (area/n^2). Also: the point lies on its triangle. */
TEST(light_sampling_chi2)
{
    enum { GRID = 5, CELLS = 2 * GRID * GRID, DRAWS = 300000 };
    scene s;
    light_set ls;
    rerror e;
    double *observed, *expected, chi2, p;
    int i, dof;
    size_t l;
    CHECK(make_light_scene(&s) == 0);
    CHECKF(lights_build(&ls, &s, &e) == 0, "%s", e.msg);
    observed = calloc(ls.count * CELLS, sizeof *observed);
    expected = calloc(ls.count * CELLS, sizeof *expected);
    CHECK(observed && expected);
    for (l = 0; l < ls.count; ++l)
        for (i = 0; i < CELLS; ++i)
            if (barycentric_cell_valid(i, GRID)) expected[l * CELLS + i] = ls.select.pmf[l] * DRAWS / (GRID * GRID);
    for (i = 0; i < DRAWS; ++i) {
        real u[4];
        light_sample ys;
        const light *lt;
        vec3 rebuilt;
        int k;
        for (k = 0; k < 4; ++k) u[k] = u_test(3, (uint32_t)i, (uint32_t)k);
        CHECK(light_sample_point(&ls, u, &ys));
        lt = &ls.lights[ys.light];
        CHECK(ys.triangle == lt->triangle);
        CHECK_NEAR(ys.pdf_area, light_pdf_area(&ls, ys.triangle), 1e-12 * ys.pdf_area);
        rebuilt = v3_add(v3_add(v3_scale(v3_from_f(lt->v0), ys.barycentric.x), v3_scale(v3_from_f(lt->v1), ys.barycentric.y)),
                         v3_scale(v3_from_f(lt->v2), 1 - ys.barycentric.x - ys.barycentric.y));
        CHECK(v3_length(v3_sub(rebuilt, v3_from_f(ys.position))) < 1e-5);
        observed[ys.light * CELLS + (size_t)barycentric_cell(ys.barycentric, GRID)] += 1;
    }
    p = chi2_test(observed, expected, ls.count * CELLS, &chi2, &dof);
    free(observed);
    free(expected);
    lights_free(&ls);
    scene_free(&s);
    CHECKF(p > 1e-3, "chi2 = %g, dof = %d, p = %g", chi2, dof, p);
}

/* Closest hit of a ray with the lights only (Möller-Trumbore in real precision; the
 * lights of make_light_scene do not occlude each other from the origin). */
static int closest_light_hit(const light_set *ls, vec3 o, vec3 d, uint32_t *which, vec3 *hit)
{
    real best = INFINITY;
    size_t i;
    for (i = 0; i < ls->count; ++i) {
        vec3 v0 = v3_from_f(ls->lights[i].v0);
        vec3 e1 = v3_sub(v3_from_f(ls->lights[i].v1), v0), e2 = v3_sub(v3_from_f(ls->lights[i].v2), v0);
        vec3 pv = v3_cross(d, e2), tv, qv;
        real det = v3_dot(e1, pv), inv, a, b, t;
        if (fabs(det) < 1e-12) continue;
        inv = 1 / det;
        tv = v3_sub(o, v0);
        a = v3_dot(tv, pv) * inv;
        if (a < 0 || a > 1) continue;
        qv = v3_cross(tv, e1);
        b = v3_dot(d, qv) * inv;
        if (b < 0 || a + b > 1) continue;
        t = v3_dot(e2, qv) * inv;
        if (t > 0 && t < best) {
            best = t;
            *which = ls->lights[i].triangle;
        }
    }
    if (best == INFINITY) return 0;
    *hit = v3_add(o, v3_scale(d, best));
    return 1;
}

/* The solid-angle pdf of NEE integrates to 1 over the directions that see a light:
 * E[p_light(x -> y(ω)) / p_sphere(ω)] = Σ_l P(l) = 1 with ω uniform on the sphere
 * (lights seen from the back count: NEE samples them too, with zero contribution). */
TEST(light_solid_angle_pdf_integrates_to_one)
{
    enum { N = 400000 };
    scene s;
    light_set ls;
    rerror e;
    double sum = 0, sum2 = 0, mean, se;
    vec3 x = v3((real)0.1, (real)0.05, (real)-0.2);
    int i;
    CHECK(make_light_scene(&s) == 0);
    CHECKF(lights_build(&ls, &s, &e) == 0, "%s", e.msg);
    for (i = 0; i < N; ++i) {
        vec3 d = warp_uniform_sphere(v2(u_test(4, (uint32_t)i, 0), u_test(4, (uint32_t)i, 1))), y;
        uint32_t tri = 0;
        double f = 0;
        if (closest_light_hit(&ls, x, d, &tri, &y)) {
            const light *lt = &ls.lights[ls.light_of_triangle[tri]];
            f = light_pdf_solid_angle(&ls, tri, x, y, v3_from_f(lt->normal)) / warp_uniform_sphere_pdf();
        }
        sum += f;
        sum2 += f * f;
    }
    mean = sum / N;
    se = sqrt((sum2 / N - mean * mean) / (N - 1));
    lights_free(&ls);
    scene_free(&s);
    CHECKF(fabs(mean - 1) < 4 * se && se < 0.02, "integral %g +- %g", mean, se);
}

/* NEE's shortcut (vertex_sampling.c): a sample's own pdf_area and d = y - x give exactly
 * light_pdf_solid_angle(triangle, x, y, ny) (pdf_area_to_solid_angle_d; docs/performance.md). */
TEST(light_sample_pdf_shortcut_exact)
{
    scene s;
    light_set ls;
    rerror e;
    uint32_t i;
    CHECK(make_light_scene(&s) == 0);
    CHECKF(lights_build(&ls, &s, &e) == 0, "%s", e.msg);
    for (i = 0; i < 20000; ++i) {
        real u[4] = {u_test(5, i, 0), u_test(5, i, 1), u_test(5, i, 2), u_test(5, i, 3)};
        vec3 x = v3(4 * u_test(6, i, 0) - 2, 4 * u_test(6, i, 1) - 2, 4 * u_test(6, i, 2) - 2), y, d, ny;
        light_sample ls_y;
        real slow, fast;
        if (!light_sample_point(&ls, u, &ls_y)) continue;
        y = v3_from_f(ls_y.position);
        ny = v3_from_f(ls_y.normal);
        d = v3_sub(y, x);
        slow = light_pdf_solid_angle(&ls, ls_y.triangle, x, y, ny);
        fast = ls_y.pdf_area > 0 ? pdf_area_to_solid_angle_d(ls_y.pdf_area, d, v3_dot(d, d), ny) : 0;
        if (!(fast == slow) || ls_y.pdf_area != light_pdf_area(&ls, ls_y.triangle)) {
            CHECKF(0, "sample %u: %.17g != %.17g", i, (double)fast, (double)slow);
            break;
        }
    }
    lights_free(&ls);
    scene_free(&s);
}

TEST(light_emission_is_one_sided)
{
    vec3 n = v3(0, -1, 0);
    rgb ke = rgb_make(1, 2, 3);
    CHECK(light_emitted(ke, n, v3(0, -1, 0)).g == 2);
    CHECK(rgb_is_black(light_emitted(ke, n, v3(0, 1, 0))));
    CHECK(rgb_is_black(light_emitted(ke, n, v3(1, 0, 0))));
    CHECK_NEAR(pdf_area_to_solid_angle(2, v3(0, 0, 0), v3(0, 3, 0), v3(0, -1, 0)), 18, 1e-12);
    CHECK_NEAR(pdf_area_to_solid_angle(2, v3(0, 0, 0), v3(0, 3, 0), v3(0, 1, 0)), 18, 1e-12);
    CHECK(pdf_area_to_solid_angle(2, v3(0, 0, 0), v3(0, 3, 0), v3(1, 0, 0)) == 0);
}
