#!/bin/sh
# ImageMagick's part of the PNG corpus (docs/images.md; not run by make). The sources
# come from make_png_corpus.c (values of tests/image_corpus.h). ImageMagick 6.9.11 (Debian 12).
#   sh tools/images/make_png_corpus.sh SRC_DIR OUT_DIR
set -eu
src=$1 out=$2
convert "$src/grey8.pgm" -define png:color-type=0 -define png:bit-depth=8 "$out/im_grey8.png"
convert "$src/grey16.pgm" -define png:color-type=0 -define png:bit-depth=16 "$out/im_grey16.png"
convert "$src/rgb8.ppm" "PNG24:$out/im_rgb8.png"
convert "$src/rgb16.ppm" "PNG48:$out/im_rgb16.png"
convert "$src/rgba8.pam" "PNG32:$out/im_rgba8.png"
convert "$src/rgba16.pam" "PNG64:$out/im_rgba16.png"
convert "$src/rgb8.ppm" -interlace PNG "PNG24:$out/im_rgb8_adam7.png"
convert "$src/pal8.ppm" "PNG8:$out/im_pal8.png"
# what each file became (colour type and depth from IHDR)
for f in "$out"/im_*.png; do
    printf '%s: ' "$f"
    od -A n -t u1 -j 24 -N 5 "$f" | awk '{print "depth " $1 ", colour type " $2 ", interlace " $5}'
done
