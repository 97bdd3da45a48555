/* The correlation metric of the MCMC mutations paper (Mutations §5, Eq. 21):
 * the sample covariance between pixels i and j over K independent renders,
 *     Cov(i, j) = 1/(K-1) sum_k (I_ki - mean_i)(I_kj - mean_j),        (Eq. 21)
 * averaged over the box of radius r centred on each pixel (clipped at the image
 * border), then over all pixels. The paper uses K = 100 and r = 8 (Table 1) and plots
 * the value against r ("average radial covariance", Fig. 9). We compute it on
 * luminance, for every radius 0..R at once, in one pass over the images
 * (docs/statistics.md, "covariance"). */
#ifndef RESTIR_COVARIANCE_H
#define RESTIR_COVARIANCE_H

#include "restir/core/error.h"
#include "restir/core/image.h"

typedef struct {
    int width, height;
    int radius;          /* largest box radius R */
    int exclude_center;  /* 1: the box average leaves out j = i (the variance term) */
    long images;         /* K so far */
    double *shift;       /* luminance of the first image (shift invariance keeps sums small) */
    double *sum;         /* per pixel: sum_k y_ki, y = luminance - shift */
    double *map_cross;   /* per pixel: sum_k y_ki * box_sum_k(i, R) */
    double *map_self;    /* per pixel: sum_k y_ki^2 */
    double *cross;       /* per radius: sum_k sum_i w_r(i) y_ki box_sum_k(i, r) */
    double *self;        /* per radius: sum_k sum_i w_r(i) y_ki^2 */
    double *sat;         /* scratch: summed-area table, (width+1) x (height+1) */
    double *y;           /* scratch: one image of y */
} covariance_accum;

int covariance_init(covariance_accum *c, int width, int height, int radius, int exclude_center, rerror *e);
void covariance_free(covariance_accum *c);
/* Adds one independent render. `name` (may be NULL) names it in messages. */
int covariance_add(covariance_accum *c, const image *img, const char *name, rerror *e);
/* per_radius[r], r = 0..R: the image average of the box-averaged covariance
 * (with exclude_center, per_radius[0] is NaN). map (may be NULL): the per-pixel box
 * average at radius R, as a grey float image. Needs K >= 2. */
int covariance_result(const covariance_accum *c, double *per_radius, image *map, rerror *e);

#endif
