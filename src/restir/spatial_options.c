/* The spatial technique's options (include/restir/restir/spatial_options.h). */
#include "restir/restir/spatial_options.h"

#include <string.h>

const char *const restir_pairing_names[] = {"disk", "paired", NULL};
const char *const spatial_algorithm_names[] = {"gris-step", "stochastic-pairwise", NULL};

void spatial_options_default(spatial_options *o)
{
    memset(o, 0, sizeof *o);
    o->algorithm = SPATIAL_GRIS_STEP;
    o->mis = MIS_TALBOT;
    o->neighbors = 6;
    o->radius = 10;
    o->pattern = NEIGHBOR_R2;
    o->pairing = RESTIR_PAIRING_DISK;
    o->eq3_reading = PAIRING_EQ3_DEFAULT;
    o->normal_cos = NEIGHBOR_DEFAULT_MIN_NORMAL_COS;
    o->depth_ratio = NEIGHBOR_DEFAULT_MAX_RELATIVE_DEPTH;
}

void spatial_neighbor_options(neighbor_options *no, const spatial_options *o)
{
    neighbor_options_default(no);
    no->pattern = o->pattern;
    no->count = o->neighbors;
    no->radius = o->radius;
    no->reject_geometry = !o->no_reject;
    no->min_normal_cos = (float)o->normal_cos;
    no->max_relative_depth = (float)o->depth_ratio;
    if (o->pairing == RESTIR_PAIRING_PAIRED) no->pattern = NEIGHBOR_PAIRED;
}

int spatial_options_validate(const spatial_options *o, rerror *e)
{
    neighbor_options no;
    if (o->algorithm != SPATIAL_GRIS_STEP && o->algorithm != SPATIAL_STOCHASTIC_PAIRWISE)
        return rerror_set(e, "spatial: unknown algorithm %d", (int)o->algorithm);
    if ((int)o->mis < 0 || (int)o->mis >= MIS_FAMILY_COUNT)
        return rerror_set(e, "spatial: unknown MIS family %d", (int)o->mis);
    if (o->pairing != RESTIR_PAIRING_DISK && o->pairing != RESTIR_PAIRING_PAIRED)
        return rerror_set(e, "spatial: unknown pairing %d", (int)o->pairing);
    if ((int)o->eq3_reading < 0 || (int)o->eq3_reading >= PAIRING_EQ3_COUNT)
        return rerror_set(e, "spatial: unknown Eq. 3 reading %d", (int)o->eq3_reading);
    if (!(o->radius >= 1) || !(o->radius <= 4096)) return rerror_set(e, "spatial: radius %g outside [1, 4096]", o->radius);
    spatial_neighbor_options(&no, o);
    return neighbor_options_validate(&no, e);
}

const char *spatial_mis_name(const spatial_options *o)
{
    return o->algorithm == SPATIAL_STOCHASTIC_PAIRWISE ? spatial_algorithm_names[SPATIAL_STOCHASTIC_PAIRWISE]
                                                       : restir_mis_names[o->mis];
}
