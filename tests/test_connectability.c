/* The reconnection criterion (include/restir/restir/connectability.h): GRIS §7.6 lobe-specific
 * roughness, the distance condition of GRIS §7.5, and the index each shift stores. */
#include <string.h>
#include "restir/restir/connectability.h"
#include "test.h"

static bsdf make_bsdf(enum material_type type, real roughness)
{
    material m;
    memset(&m, 0, sizeof m);
    m.type = type;
    m.diffuse = rgb_gray((real)0.5);
    m.specular = rgb_gray(1);
    m.roughness = roughness;
    m.ior = (real)1.5;
    return bsdf_from_material(&m);
}

TEST(connectability_lobe_roughness)
{
    bsdf plastic_glossy = make_bsdf(MAT_PLASTIC, (real)0.15), plastic_rough = make_bsdf(MAT_PLASTIC, (real)0.5);
    bsdf glass = make_bsdf(MAT_DIELECTRIC, 0), metal = make_bsdf(MAT_CONDUCTOR, (real)0.1);
    bsdf rough_glass = make_bsdf(MAT_ROUGH_DIELECTRIC, (real)0.3), lambert = make_bsdf(MAT_LAMBERT, 0);
    real t = (real)0.2;
    /* BSDF-sampled vertices: the sampled lobe alone (GRIS §7.6). */
    CHECK(rc_vertex_is_rough(&plastic_glossy, 0, t) && !rc_vertex_is_rough(&plastic_glossy, 1, t));
    CHECK(rc_vertex_is_rough(&plastic_rough, 0, t) && rc_vertex_is_rough(&plastic_rough, 1, t));
    CHECK(!rc_vertex_is_rough(&glass, 0, t) && !rc_vertex_is_rough(&glass, 1, t));
    CHECK(!rc_vertex_is_rough(&metal, 0, t) && rc_vertex_is_rough(&metal, 0, (real)0.05));
    CHECK(rc_vertex_is_rough(&rough_glass, 0, t) && rc_vertex_is_rough(&rough_glass, 1, t));
    CHECK(rc_vertex_is_rough(&lambert, 0, t) && !rc_vertex_is_rough(&lambert, 1, t)); /* no lobe 1 */
    /* NEE vertices: rough if any lobe is; light vertices always. */
    CHECK(rc_vertex_is_rough(&plastic_glossy, PATH_LOBE_NEE, t) && !rc_vertex_is_rough(&glass, PATH_LOBE_NEE, t));
    CHECK(!rc_vertex_is_rough(&metal, PATH_LOBE_NEE, t));
    CHECK(rc_vertex_is_rough(NULL, PATH_LOBE_NONE, t));
}

static rc_vertex vtx(real x, int rough)
{
    rc_vertex v;
    v.position = v3(x, 0, 0);
    v.at_infinity = 0;
    v.rough = rough;
    return v;
}

TEST(connectability_index_per_shift)
{
    restir_context c;
    rc_vertex v[PATH_MAX_LENGTH + 1];
    memset(&c, 0, sizeof c);
    c.rc.roughness_threshold = (real)0.2;
    c.rc.min_distance = 1;
    v[0] = vtx(0, 0);
    /* x1 glossy, x2..x4 rough; x2 -> x3 too short, x3 -> x4 long enough. */
    v[1] = vtx(0, 0);
    v[2] = vtx(5, 1);
    v[3] = vtx((real)5.5, 1);
    v[4] = vtx(8, 1);
    c.shift = RESTIR_SHIFT_RECONNECTION;
    CHECK(rc_select(&c, v, 4) == 2); /* y2 = x2 whatever the criterion says */
    c.shift = RESTIR_SHIFT_REPLAY;
    CHECK(rc_select(&c, v, 4) == PATH_RC_NONE);
    c.shift = RESTIR_SHIFT_HYBRID;
    CHECK(rc_select(&c, v, 4) == 4); /* (x1,x2): x1 glossy; (x2,x3): 0.5 < d_min; (x3,x4) */
    CHECK(rc_pair_test(&c.rc, &v[1], &v[2], 0) == SHIFT_FAIL_RC_ROUGHNESS);
    CHECK(rc_pair_test(&c.rc, &v[2], &v[3], 0) == SHIFT_FAIL_RC_DISTANCE);
    CHECK(rc_pair_test(&c.rc, &v[3], &v[4], 0) == SHIFT_OK);
    CHECK(rc_select(&c, v, 3) == PATH_RC_NONE);
    v[1].rough = 1;
    CHECK(rc_select(&c, v, 4) == 2);
    c.rc.min_distance = (real)5.0; /* exactly the length of x1 -> x2: allowed (>=) */
    CHECK(rc_select(&c, v, 4) == 2);
}
