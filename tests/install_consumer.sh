#!/usr/bin/env bash
# Installs the build tree into a scratch prefix and builds and runs tests/consumer against it; with
# OpenImageIO (with_oiio 1), the installed command writes a PNG through its installed image module.
# Usage: install_consumer.sh <houle build dir> <houle source dir> <scratch dir> <with_oiio 0|1>
set -euo pipefail
build=$1 src=$2 scratch=$3 with_oiio=$4
rm -rf "$scratch"
cmake --install "$build" --prefix "$scratch/prefix" >/dev/null
cmake -S "$src/tests/consumer" -B "$scratch/build" -G Ninja -DCMAKE_PREFIX_PATH="$scratch/prefix" >/dev/null
cmake --build "$scratch/build" >/dev/null
"$scratch/build/consumer"
if [ "$with_oiio" = 1 ]; then
  "$scratch/prefix/bin/houle" render --frames 1 --size 16x9 --quality draft --out "$scratch/frame_%d.png" >/dev/null
  [ -s "$scratch/frame_0.png" ] || { echo "install_consumer: the installed houle wrote no PNG"; exit 1; }
fi
