#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# check-licence.sh SOURCE_DIR: every source file of the project (C++, CMake, shell) names its
# licence in its first lines (SPDX-License-Identifier: Apache-2.0, the LICENSE file's), and the
# LICENSE file is there. Lists the files that do not; exits 1 then.
set -euo pipefail
root=$1
cd "$root"
if [ ! -f LICENSE ] || ! grep -q "Apache License" LICENSE; then
  echo "check-licence.sh: LICENSE (Apache-2.0) is missing" >&2
  exit 1
fi
mapfile -t files < <(find core collision render app tests -name '*.h' -o -name '*.cpp' \
  -o -name 'CMakeLists.txt' -o -name '*.sh' | sort; echo CMakeLists.txt; echo tissuesim.sh; echo .ci/run)
missing=()
for file in "${files[@]}"; do
  if ! head -3 "$file" | grep -q "SPDX-License-Identifier: Apache-2.0"; then missing+=("$file"); fi
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "check-licence.sh: ${#missing[@]} of ${#files[@]} files lack 'SPDX-License-Identifier: Apache-2.0' in their first three lines:" >&2
  printf '  %s\n' "${missing[@]}" >&2
  exit 1
fi
echo "check-licence.sh: ${#files[@]} files carry the licence"
