#!/usr/bin/env bash
# Fails when a header under include/unisph/ includes a module above its own, so that the
# modules can be read bottom-up (docs/architecture.md, "Module graph"). The order below is the
# graph's: a module may include itself and the modules before it, never one after it.
set -euo pipefail
cd "$(dirname "$0")/.."
order=(core io smoothing memory exec dynamics motion particles comm iter neighbor grid geometry levelset relaxation shape sph solver)
declare -A rank
for i in "${!order[@]}"; do rank[${order[$i]}]=$i; done
status=0
while IFS= read -r file; do
  module=${file#include/unisph/}
  module=${module%%/*}
  [[ $module == *.hpp ]] && continue  # unisph.hpp: the umbrella header includes the core it names
  if [[ -z ${rank[$module]+x} ]]; then
    echo "$file: module '$module' is not in the order of scripts/check_includes.sh"
    status=1
    continue
  fi
  while IFS= read -r line; do
    number=${line%%:*}
    target=$(sed -E 's#.*"unisph/([a-z_]+)/.*#\1#' <<<"$line")
    if [[ -z ${rank[$target]+x} ]]; then
      echo "$file:$number: includes module '$target', which is not in the order"
      status=1
    elif ((rank[$target] > rank[$module])); then
      echo "$file:$number: '$module' includes '$target', a module above it (order: ${order[*]})"
      status=1
    fi
  done < <(grep -n '#include "unisph/[a-z_]*/' "$file" || true)
done < <(find include/unisph -name '*.hpp' -o -name '*.cuh' | sort)
exit $status
