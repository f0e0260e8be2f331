#!/bin/sh
# Build a relocatable single-node Open MPI 4.1.4 bundle from Debian 12 packages.
# Used for the rank sweeps on a lent machine without Open MPI (docs/distributed.md, "Measured"):
#   tools/ompi_bundle/make_bundle.sh .ompi   (here, on Debian 12 with openmpi-bin installed)
#   then there: . .ompi/env.sh; $MPIRUN -np 16 csm search MESH --setup S.json -o R.json
set -eu
DEST=${1:?usage: make_bundle.sh DEST}
S=/usr/lib/x86_64-linux-gnu
rm -rf "$DEST"; mkdir -p "$DEST"
L=$DEST/usr/lib/x86_64-linux-gnu
mkdir -p "$DEST/usr/bin" "$L/openmpi/lib/openmpi3" "$L/pmix2/lib/pmix" "$L/pmix2/share" "$L/ompi-fallback" "$DEST/usr/share" "$DEST/etc/openmpi"
# executables
for b in orterun orted ompi_info; do cp -a /usr/bin/$b "$DEST/usr/bin/"; done
ln -s orterun "$DEST/usr/bin/mpirun"; ln -s orterun "$DEST/usr/bin/mpiexec"
# shared libs (real file + soname link), Debian layout in $L
cplib() { # $1 = soname path in $S, $2 = target dir
  real=$(readlink -f "$1"); cp -a "$real" "$2/"
  [ "$(basename "$real")" = "$(basename "$1")" ] || ln -sf "$(basename "$real")" "$2/$(basename "$1")"
}
for so in libmpi.so.40 libopen-rte.so.40 libopen-pal.so.40 libmca_common_sm.so.40 libmca_common_ompio.so.41 \
          libhwloc.so.15 libevent_core-2.1.so.7 libevent_pthreads-2.1.so.7 libmunge.so.2; do
  cplib $S/$so "$L"
done
# only used when the host lacks them (env.sh checks ldconfig)
for so in libudev.so.1 libz.so.1; do cplib $S/$so "$L/ompi-fallback"; done
# PMIx (external, its own prefix)
cp -a $S/pmix2/lib/libpmix.so.2.6.2 "$L/pmix2/lib/"
ln -s libpmix.so.2.6.2 "$L/pmix2/lib/libpmix.so.2"
ln -s pmix2/lib/libpmix.so.2.6.2 "$L/libpmix.so.2"
cp -a $S/pmix2/lib/pmix/*.so "$L/pmix2/lib/pmix/"
cp -a $S/pmix2/share/pmix $S/pmix2/share/pmix-mca-params.conf "$L/pmix2/share/"
rm -f "$L/pmix2/share/pmix/pmix-valgrind.supp" "$L/pmix2/share/pmix/pmixcc-wrapper-data.txt"
# MCA plugins: drop oshmem, ucx, ofi, verbs/openib, psm, netlink, monitoring, cm
for f in $S/openmpi/lib/openmpi3/*.so; do
  n=$(basename $f)
  case $n in
    mca_atomic_*|mca_memheap_*|mca_scoll_*|mca_spml_*|mca_sshmem_*|*ucx*|*ofi*|mca_btl_openib*|mca_mtl_*|mca_pml_cm*|\
    *monitoring*|mca_reachable_netlink*|mca_btl_tcp*|mca_btl_sm.so|mca_pmix_flux*|mca_schizo_flux*|mca_schizo_jsm*|libompi_dbg_msgq*) continue;;
  esac
  cp -a $f "$L/openmpi/lib/openmpi3/"
done
# help texts (needed for readable error messages)
mkdir -p "$DEST/usr/share/openmpi"
cp -a /usr/share/openmpi/help-*.txt /usr/share/openmpi/amca-param-sets "$DEST/usr/share/openmpi/"
rm -f "$DEST"/usr/share/openmpi/help-oshmem-* "$DEST"/usr/share/openmpi/help-shmem-*
cp -a /etc/openmpi/openmpi-default-hostfile "$DEST/etc/openmpi/"
H=$(dirname "$0"); [ -f "$H/env.sh" ] && [ "$H/env.sh" != "$DEST/env.sh" ] && cp "$H/env.sh" "$H/make_bundle.sh" "$DEST/"
[ -f "$H/etc/openmpi/openmpi-mca-params.conf" ] && cp "$H/etc/openmpi/openmpi-mca-params.conf" "$DEST/etc/openmpi/" || true
