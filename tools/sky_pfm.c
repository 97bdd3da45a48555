/* Writes the procedural sky of scenes/courtyard.scene (docs/scenes.md): a 32 x 16 RGB PFM,
 * little-endian, in the map convention of docs/environment.md (row 0 = zenith).
 *   cc -O2 -std=c99 -o /tmp/sky_pfm tools/sky_pfm.c -lm && /tmp/sky_pfm scenes/courtyard-sky.pfm
 * Above the horizon: a blue zenith fading to a pale horizon, brighter towards u = 0.2 (the
 * side of the sun); below: a dim brown ground. Deterministic (no random numbers). */
#include <math.h>
#include <stdio.h>

int main(int argc, char **argv)
{
    enum { W = 32, H = 16 };
    float px[W * H * 3];
    FILE *f;
    int x, y;
    if (argc != 2) {
        fprintf(stderr, "usage: sky_pfm OUT.pfm\n");
        return 2;
    }
    for (y = 0; y < H; ++y)
        for (x = 0; x < W; ++x) {
            double theta = 3.14159265358979 * (y + 0.5) / H, up = cos(theta);
            double u = (x + 0.5) / W, glow = 1 + 0.6 * exp(-20 * (u - 0.2) * (u - 0.2));
            float *p = px + 3 * ((H - 1 - y) * W + x); /* PFM rows run bottom to top */
            if (up > 0) {
                double t = pow(up, 0.5);
                p[0] = (float)(glow * (0.9 - 0.6 * t));
                p[1] = (float)(glow * (1.0 - 0.45 * t));
                p[2] = (float)(glow * (1.1 - 0.1 * t));
            } else {
                p[0] = 0.25f;
                p[1] = 0.2f;
                p[2] = 0.15f;
            }
        }
    f = fopen(argv[1], "wb");
    if (!f) return 1;
    fprintf(f, "PF\n%d %d\n-1.0\n", W, H);
    fwrite(px, sizeof px, 1, f); /* little-endian hosts (the scale -1 says so) */
    return fclose(f) != 0;
}
