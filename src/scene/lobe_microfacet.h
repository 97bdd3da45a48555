/* Private to src/scene. The GGX microfacet lobes (lobe_microfacet.c): glossy reflection and
 * transmission, sampled by visible normals, with exact inverses. */
#ifndef RESTIR_SRC_SCENE_LOBE_MICROFACET_H
#define RESTIR_SRC_SCENE_LOBE_MICROFACET_H

#include "lobes.h"

extern const lobe_ops lobe_glossy_reflection_ops;
extern const lobe_ops lobe_glossy_transmission_ops;

/* Fresnel of the material's specular interface for a microfacet (or macro) cosine:
 * Schlick with F0 = Ks for conductors, Ks * exact dielectric Fresnel otherwise. */
rgb lobe_specular_fresnel(const lobe_view *v, real cos_wo_m);

#endif
