# The harness the shell tests share (source it after setting houle and src): a work folder removed on
# exit, the pass and fail counts, and expect.
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
pass=0 fail=0

# expect <name> <exit code> <regex the output must match> <command...>
expect() {
  local name=$1 code=$2 pattern=$3; shift 3
  local out rc
  out=$("$@" 2>&1); rc=$?
  if [ "$rc" -eq "$code" ] && grep -qE -- "$pattern" <<<"$out"; then
    pass=$((pass + 1))
  else
    fail=$((fail + 1))
    printf 'FAIL %s: exit %s (want %s), output:\n%s\n(want /%s/)\n' "$name" "$rc" "$code" "$out" "$pattern"
  fi
}
