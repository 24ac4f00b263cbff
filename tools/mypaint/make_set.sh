#!/bin/sh
# Paints every truth under ROOT/truth (cargo run --release --example truth_dump -- ROOT) with
# each brush and seed, in both cases: `texture` (the clean truth, brush texture alone) and
# `faults` (the truth painted 10° off the scene's light, with strays, flat tones and noise).
# Writes ROOT/paintings/MODEL/PRESET-BRUSH-CASE-sSEED.png; existing files are kept.
# CASES picks others, one fault at a time: `off` (the 10°-off truth, brush texture alone),
# `strays`, `tones` or `noise` (the truth with that fault alone).
#
#   tools/mypaint/make_set.sh ROOT [SHRINK]
#   BRUSHES="charcoal oil" SEEDS="1 2 3" JOBS=2 tools/mypaint/make_set.sh ROOT
#   CASES="off strays tones noise" SEEDS="1 2" tools/mypaint/make_set.sh ROOT
set -eu
root=$1
shrink=${2:-1}
here=$(cd "$(dirname "$0")" && pwd)
brushes=${BRUSHES:-"charcoal pencil oil acrylic watercolour"}
seeds=${SEEDS:-"1 2 3"}
cases=${CASES:-"texture faults"}
for case in $cases; do
    case $case in
        texture | faults | off | strays | tones | noise) ;;
        *) echo "make_set.sh: unknown case '$case' (texture, faults, off, strays, tones, noise)" >&2; exit 2 ;;
    esac
done
for truth in "$root"/truth/*/*-clean.png; do
    model=$(basename "$(dirname "$truth")")
    preset=$(basename "$truth" -clean.png)
    off="${truth%-clean.png}-off.png"
    mkdir -p "$root/paintings/$model"
    for brush in $brushes; do
        for seed in $seeds; do
            for case in $cases; do
                out="$root/paintings/$model/$preset-$brush-$case-s$seed.png"
                [ -e "$out" ] && continue
                args="--preset $brush --seed $seed --shrink $shrink"
                case $case in
                    texture) echo "$truth $out $args" ;;
                    faults) echo "$off $out $args --faults" ;;
                    off) echo "$off $out $args" ;;
                    *) echo "$truth $out $args --faults $case" ;;
                esac
            done
        done
    done
done | xargs -P "${JOBS:-2}" -L 1 /usr/bin/python3 "$here/paint_sphere.py"
