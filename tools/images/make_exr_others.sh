#!/bin/sh
# EXR files written by programs other than a direct libOpenEXR call (docs/images.md; not
# run by make): ImageMagick 6.9.11 `convert` (its own EXR coder: half RGB(A); it has no
# RLE for EXR, so NONE, ZIP and PIZ), and
# OpenEXR's command-line tools applied to a file OUR writer made (exrmakepreview adds a
# preview attribute, exrstdattr standard attributes, exrmultipart -convert ...).
# The expected values of ImageMagick's files are what libOpenEXR reads from them
# (im_exr_expected.txt); the tools' files keep our writer's values (tests/image_corpus.h).
#   sh tools/images/make_exr_others.sh MAKE_EXR_CORPUS PNM_SOURCE_DIR OUT_DIR
set -eu
tool=$1 src=$2 out=$3
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
convert "$src/rgb16.ppm" -compress Zip "$out/im_zip.exr"
convert "$src/rgba16.pam" -compress Piz "$out/im_piz.exr"
convert "$src/grey16.pgm" -compress None "$out/im_none.exr"
"$tool" dump "$out"/im_zip.exr "$out"/im_piz.exr "$out"/im_none.exr > "$out/im_exr_expected.txt"
# our writer's 37 x 23 half RGB (ZIP), then OpenEXR's tools rewrite it
"$tool" oracle "$tmp" > /dev/null
exrmakepreview -w 12 "$tmp/ours_zip_half.exr" "$out/tool_preview.exr"
cp "$tmp/ours_zip_half.exr" "$tmp/attr.exr"
exrstdattr -owner restir -comments "exrstdattr of our writer's file" -chromaticities 0.64 0.33 0.3 0.6 0.15 0.06 0.3127 0.329 \
    "$tmp/attr.exr" "$out/tool_stdattr.exr"
for f in "$out"/im_*.exr "$out"/tool_*.exr; do exrheader "$f" | grep -E '^file|compression|channels|^    [A-Z]' ; done
