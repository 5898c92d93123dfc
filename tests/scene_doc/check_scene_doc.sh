#!/usr/bin/env bash
# Fails when docs/scenes.md is not what the generator prints from the scene key table.
# Usage: check_scene_doc.sh <houle_gen_scene_doc binary> <docs/scenes.md>
set -uo pipefail
gen=$1 doc=$2
expected=$("$gen") || { echo "scene_doc_current: $gen failed" >&2; exit 1; }
if diff -u "$doc" <(printf '%s\n' "$expected"); then
  exit 0
fi
echo "scene_doc_current: docs/scenes.md differs from the scene key table (sim/src/scene_keys.cpp):" \
  "regenerate it with scripts/regen-scene-doc and commit it" >&2
exit 1
