#!/bin/sh
# Paints every truth under ROOT/truth (cargo run --release --example truth_dump -- ROOT) with
# each brush and seed, in both cases: `texture` (the clean truth, brush texture alone) and
# `faults` (the truth painted 10° off the scene's light, with strays, flat tones and noise).
# Writes ROOT/paintings/MODEL/PRESET-BRUSH-CASE-sSEED.png; existing files are kept.
#
#   tools/mypaint/make_set.sh ROOT [SHRINK]
#   BRUSHES="charcoal oil" SEEDS="1 2 3" JOBS=2 tools/mypaint/make_set.sh ROOT
set -eu
root=$1
shrink=${2:-1}
here=$(cd "$(dirname "$0")" && pwd)
brushes=${BRUSHES:-"charcoal pencil oil acrylic watercolour"}
seeds=${SEEDS:-"1 2 3"}
for truth in "$root"/truth/*/*-clean.png; do
    model=$(basename "$(dirname "$truth")")
    preset=$(basename "$truth" -clean.png)
    mkdir -p "$root/paintings/$model"
    for brush in $brushes; do
        for seed in $seeds; do
            out="$root/paintings/$model/$preset-$brush"
            [ -e "$out-texture-s$seed.png" ] || echo "$truth $out-texture-s$seed.png --preset $brush --seed $seed --shrink $shrink"
            [ -e "$out-faults-s$seed.png" ] || echo "${truth%-clean.png}-off.png $out-faults-s$seed.png --preset $brush --seed $seed --shrink $shrink --faults"
        done
    done
done | xargs -P "${JOBS:-2}" -L 1 /usr/bin/python3 "$here/paint_sphere.py"
