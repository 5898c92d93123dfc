#!/usr/bin/env bash
# Runs a test program (e.g. under an emulated CPU) and fails unless it exits 0 *and* reports that the
# dispatcher chose <isa>. Usage: run_expecting_isa.sh <isa> <command>...
set -uo pipefail
want=$1; shift
out=$("$@" 2>&1); rc=$?
printf '%s\n' "$out"
[ $rc -eq 0 ] || { echo "run_expecting_isa: exit code $rc"; exit 1; }
grep -q "houle: active ISA ${want};" <<<"$out" || { echo "run_expecting_isa: expected ISA ${want}"; exit 1; }
