#!/usr/bin/env bash
# cmake/commit_stamp.cmake: the commit a build names. In a scratch repository: a clean tree gives
# its 12-digit commit, a changed source file adds "+changes", a changed doc does not, and a
# folder outside git gives "unknown". Usage: commit_stamp.sh CMAKE STAMP_SCRIPT
set -euo pipefail
cmake_bin=$1 stamp=$2
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
stamp_of() {
  "$cmake_bin" -DSOURCE_DIR="$1" -DOUTPUT="$scratch/out.inc" -P "$stamp"
  sed -n 's/^#define CHAINMAIL_COMMIT "\(.*\)"$/\1/p' "$scratch/out.inc"
}
fail() { echo "commit_stamp: $*" >&2; exit 1; }
repo=$scratch/repo
mkdir -p "$repo/core" "$repo/docs"
echo "int x;" > "$repo/core/a.cpp"
echo "notes" > "$repo/docs/a.md"
git -C "$repo" init -q
git -C "$repo" add -A
git -C "$repo" -c user.name=t -c user.email=t@t commit -qm first
commit=$(git -C "$repo" rev-parse --short=12 HEAD)
[ "$(stamp_of "$repo")" = "$commit" ] || fail "clean tree: $(stamp_of "$repo"), not $commit"
echo "changed" >> "$repo/docs/a.md"
[ "$(stamp_of "$repo")" = "$commit" ] || fail "a changed doc: $(stamp_of "$repo"), not $commit"
echo "int y;" >> "$repo/core/a.cpp"
[ "$(stamp_of "$repo")" = "$commit+changes" ] || fail "a changed source: $(stamp_of "$repo")"
mkdir -p "$scratch/plain"
[ "$(stamp_of "$scratch/plain")" = "unknown" ] || fail "outside git: $(stamp_of "$scratch/plain")"
echo "commit_stamp: ok ($commit)"
