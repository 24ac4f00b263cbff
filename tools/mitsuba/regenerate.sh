#!/bin/sh
# Regenerates tests/data/mitsuba/: brdfpaint writes the suite's scenes (glTF), Mitsuba 3
# renders them (render_suite.py). Needs Python with requirements.txt installed (PYTHON,
# default python3) and libLLVM 19 for Dr.Jit's CPU backend (README.md beside this file).
set -eu
cd "$(dirname "$0")/../.."
: "${PYTHON:=python3}"
# Dr.Jit finds a libLLVM by itself, but may take an older one: LLVM 15 crashed in code
# generation on our machines.
: "${DRJIT_LIBLLVM_PATH:=/usr/lib/x86_64-linux-gnu/libLLVM-19.so}"
export DRJIT_LIBLLVM_PATH
scenes=$(mktemp -d)
trap 'rm -rf "$scenes"' EXIT
cargo run --release --example mitsuba_suite -- scenes "$scenes" >/dev/null
"$PYTHON" tools/mitsuba/render_suite.py --scenes "$scenes" --out tests/data/mitsuba "$@"
