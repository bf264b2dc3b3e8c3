#!/bin/sh
# granule --version: "granule X.Y.Z (commit C)", C from `git describe --always --dirty` when
# the tree was configured: a commit this repository has (so a stale or made-up name fails),
# or "unknown" when the source is not a git checkout.
# Usage: version_test.sh GRANULE SOURCE_DIR
set -eu
line=$("$1" --version)
commit=$(printf '%s\n' "$line" | sed -n 's/^granule [0-9][0-9.]* (commit \(.*\))$/\1/p')
[ -n "$commit" ] || { echo "FAILED: '$line' does not read 'granule X.Y.Z (commit C)'"; exit 1; }
if git -C "$2" rev-parse --git-dir > /dev/null 2>&1; then
  hash=${commit%-dirty}
  git -C "$2" cat-file -e "$hash^{commit}" 2> /dev/null ||
    { echo "FAILED: '$line' names '$hash', which is no commit of $2"; exit 1; }
else
  [ "$commit" = unknown ] || { echo "FAILED: no git checkout, yet the commit is '$commit'"; exit 1; }
fi
echo "version_test ok: $line"
