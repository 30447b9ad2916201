#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# check-format.sh SOURCE_DIR: every C++ file of the project's libraries, program and tests is as
# clang-format (the repository's .clang-format) writes it. Lists the files that are not, with
# the command that fixes them; exits 1 then, 2 when clang-format is missing.
set -euo pipefail
root=$1
format=$(command -v clang-format-14 || command -v clang-format || true)
if [ -z "$format" ]; then
  echo "check-format.sh: clang-format not found (Debian: apt-get install clang-format)" >&2
  exit 2
fi
cd "$root"
mapfile -t files < <(find core collision render app tests -name '*.h' -o -name '*.cpp' | sort)
if [ ${#files[@]} -eq 0 ]; then
  echo "check-format.sh: no C++ files under $root" >&2
  exit 2
fi
unformatted=()
for file in "${files[@]}"; do
  if ! "$format" --style=file --dry-run --Werror "$file" >/dev/null 2>&1; then
    unformatted+=("$file")
  fi
done
if [ ${#unformatted[@]} -gt 0 ]; then
  echo "check-format.sh: ${#unformatted[@]} of ${#files[@]} files differ from clang-format's layout:" >&2
  printf '  %s\n' "${unformatted[@]}" >&2
  echo "fix: (cd $root && $format -i ${unformatted[*]})" >&2
  exit 1
fi
echo "check-format.sh: ${#files[@]} files as clang-format writes them"
