#!/bin/bash
# SPDX-License-Identifier: GPL-2.0-or-later
# Pack build/liggghts with every shared library it and Open MPI need (glibc
# and the dynamic loader included) into one relocatable tarball, so that the
# benchmarks can run on a machine that has neither LIGGGHTS nor MPI (the
# 16-core machine used for the scaling measurements in docs/studies/cpt-cost.md and
# docs/studies/performance.md). Usage: bench/device/make_bundle.sh OUT.tar.xz
# On the target: tar xf OUT.tar.xz -C DIR; export CRUSH_BUNDLE=DIR/bundle; DIR/bundle/bin/mpirun -np 4 DIR/bundle/bin/liggghts -in ...
set -euo pipefail
repo="$(cd "$(dirname "$0")/../.." && pwd)"
out="$(realpath -m "${1:?usage: make_bundle.sh OUT.tar.xz}")"
stage="$(mktemp -d)"
b="$stage/bundle"
ompi_lib=/usr/lib/x86_64-linux-gnu/openmpi/lib
mkdir -p "$b/bin" "$b/lib" "$b/usr/bin" "$b/usr/lib/x86_64-linux-gnu/openmpi/lib" "$b/usr/share"
cp "$repo/build/liggghts" "$b/bin/liggghts.real"
cp /usr/bin/orterun "$b/usr/bin/orterun"
cp -r "$ompi_lib/openmpi3" "$b/usr/lib/x86_64-linux-gnu/openmpi/lib/"
cp -r /usr/share/openmpi "$b/usr/share/" 2>/dev/null || true
# Debian's Open MPI uses the external PMIx, whose plugins sit under its own prefix
pmix_prefix=/usr/lib/x86_64-linux-gnu/pmix2
cp -r "$pmix_prefix" "$b/pmix2"
# every library needed by the binary, orterun and the MCA plugins
{ ldd "$repo/build/liggghts"; ldd /usr/bin/orterun; for f in "$ompi_lib"/openmpi3/*.so "$pmix_prefix"/lib/pmix/*.so; do ldd "$f"; done; } \
  | awk '/=> \//{print $3} /^\t\/lib64\/ld-linux/{print $1}' | sort -u | while read -r so; do
    cp -L "$so" "$b/lib/"
  done
cp -L /lib64/ld-linux-x86-64.so.2 "$b/lib/"
cat > "$b/bin/liggghts" <<'W'
#!/bin/sh
# CRUSH_BUNDLE names the bundle when this wrapper is run from a copy elsewhere
d="${CRUSH_BUNDLE:-$(cd "$(dirname "$0")/.." && pwd)}"
exec "$d/lib/ld-linux-x86-64.so.2" --library-path "$d/lib" "$d/bin/liggghts.real" "$@"
W
cat > "$b/bin/mpirun" <<'W'
#!/bin/sh
# Open MPI relocated under the bundle; shared-memory transport without
# single-copy (not available in every sandbox), no ssh launcher, no binding.
d="$(cd "$(dirname "$0")/.." && pwd)"
export OPAL_PREFIX="$d/usr" PMIX_INSTALL_PREFIX="$d/pmix2"
export PMIX_MCA_mca_base_component_path="$d/pmix2/lib/pmix" PMIX_MCA_pcompress_base_silence_warning=1
export OMPI_MCA_plm=isolated OMPI_MCA_btl=self,vader OMPI_MCA_pml=ob1
export OMPI_MCA_btl_vader_single_copy_mechanism=none OMPI_MCA_hwloc_base_binding_policy=none
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
exec "$d/lib/ld-linux-x86-64.so.2" --library-path "$d/lib" "$d/usr/bin/orterun" "$@"
W
chmod +x "$b/bin/liggghts" "$b/bin/mpirun"
tar -C "$stage" -cJf "$out" bundle
rm -rf "$stage"
ls -la "$out"
