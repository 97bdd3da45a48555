/* Colour maps for error images: t in [0,1] (clamped; NaN -> 0) to 8-bit sRGB. */
#ifndef RESTIR_COLORMAP_H
#define RESTIR_COLORMAP_H

void colormap_magma(double t, unsigned char rgb[3]);
void colormap_viridis(double t, unsigned char rgb[3]);

#endif
