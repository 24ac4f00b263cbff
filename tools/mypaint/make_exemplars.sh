#!/bin/sh
# Paints sphere-on-table exemplars (paint_exemplar.py) with each brush, layout, style and
# seed into OUT, then collects their circles (and, in the hidden layout, the y from which
# something in front hides the sphere) into OUT/truth.csv, which
# `cargo run --release --example disk_pictures -- --judge OUT` reads. Existing files are kept.
#
#   tools/mypaint/make_exemplars.sh OUT
#   BRUSHES="oil pencil" SEEDS="1 2 3" JOBS=2 tools/mypaint/make_exemplars.sh OUT
set -eu
out=$1
here=$(cd "$(dirname "$0")" && pwd)
brushes=${BRUSHES:-"charcoal pencil oil acrylic watercolour"}
seeds=${SEEDS:-"1 2"}
mkdir -p "$out"
for brush in $brushes; do
    for seed in $seeds; do
        for layout in middle edge hidden; do
            for style in lambert toon; do
                pic="$out/$brush-$layout-$style-s$seed.jpg"
                [ -e "$pic" ] || echo "$pic --preset $brush --seed $seed --layout $layout --style $style"
            done
        done
    done
done | xargs -P "${JOBS:-2}" -L 1 /usr/bin/python3 "$here/paint_exemplar.py"
{
    echo "name,cx,cy,r,front"
    for t in "$out"/*.txt; do
        name=$(basename "$t" .txt).jpg
        set -- $(cat "$t")
        echo "$name,$1,$2,$3,${4:-}"
    done
} > "$out/truth.csv.part" && mv "$out/truth.csv.part" "$out/truth.csv"
