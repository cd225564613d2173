#!/usr/bin/env bash
# Install the Debian packages phmech builds against, when they are missing.
# As root it runs apt-get; otherwise it prints the exact command and fails.
set -euo pipefail
pkgs=(libsundials-dev libsuitesparse-dev liblapack-dev libblas-dev pkg-config)
# A package counts as present when its marker file exists (cheaper and more robust than dpkg queries).
markers=(/usr/include/ida/ida.h /usr/include/suitesparse/klu.h
         /usr/lib/x86_64-linux-gnu/liblapack.so /usr/lib/x86_64-linux-gnu/libblas.so /usr/bin/pkg-config)
missing=()
for i in "${!pkgs[@]}"; do
  m=${markers[$i]}
  # libraries may live under another multiarch triplet
  if [[ $m == /usr/lib/x86_64-linux-gnu/* ]]; then
    ls /usr/lib/*/"$(basename "$m")" >/dev/null 2>&1 && continue
  else
    [ -e "$m" ] && continue
  fi
  missing+=("${pkgs[$i]}")
done
[ ${#missing[@]} -eq 0 ] && exit 0
cmd="apt-get update && apt-get install -y --no-install-recommends ${missing[*]}"
if [ "$(id -u)" -ne 0 ]; then
  echo "phmech needs the Debian packages: ${missing[*]}" >&2
  echo "Run as root:  $cmd" >&2
  exit 1
fi
echo "Installing Debian packages: ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
apt-get update -qq
apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
