# Source from the folder that holds .ompi:   . .ompi/env.sh
# (or set OMPI_BUNDLE=/abs/path/to/.ompi before sourcing). POSIX sh.
# Relocatable Debian 12 Open MPI 4.1.4 + PMIx 4.2.2, single-node (self,vader).
if [ -z "${OMPI_BUNDLE:-}" ]; then
  if [ -n "${BASH_SOURCE:-}" ]; then
    OMPI_BUNDLE=$(cd "$(dirname "$BASH_SOURCE")" && pwd)
  else
    OMPI_BUNDLE=$PWD/.ompi
  fi
fi
if [ ! -x "$OMPI_BUNDLE/usr/bin/orterun" ]; then
  echo "env.sh: no Open MPI bundle at $OMPI_BUNDLE (source it from the folder holding .ompi, or set OMPI_BUNDLE)" >&2
  return 1 2>/dev/null || exit 1
fi
OMPI_BUNDLE=$(cd "$OMPI_BUNDLE" && pwd)
_ob_lib=$OMPI_BUNDLE/usr/lib/x86_64-linux-gnu
export OMPI_BUNDLE
export OPAL_PREFIX="$OMPI_BUNDLE/usr"
export OPAL_SYSCONFDIR="$OMPI_BUNDLE/etc/openmpi"
export OPAL_PKGDATADIR="$OMPI_BUNDLE/usr/share/openmpi"
export OPAL_PKGLIBDIR="$_ob_lib/openmpi/lib/openmpi3"
_ob_px=$_ob_lib/pmix2
# Debian configured PMIx dirs as absolute paths, so PMIX_PREFIX alone does not move them
export PMIX_PREFIX="$_ob_px" PMIX_EXEC_PREFIX="$_ob_px" PMIX_LIBDIR="$_ob_px/lib" PMIX_PKGLIBDIR="$_ob_px/lib/pmix"
export PMIX_DATAROOTDIR="$_ob_px/share" PMIX_DATADIR="$_ob_px/share" PMIX_SYSCONFDIR="$_ob_px/share" PMIX_PKGDATADIR="$_ob_px/share/pmix"
export PMIX_MCA_mca_base_component_path="$_ob_px/lib/pmix"
export PMIX_MCA_mca_base_component_show_load_errors=0
export PATH="$OMPI_BUNDLE/usr/bin:$PATH"
_ob_ld="$_ob_lib:$_ob_lib/pmix2/lib"
# libudev/libz: use the host's copies when present, else the bundled ones
for _ob_so in libudev.so.1 libz.so.1; do
  if ! { command -v ldconfig >/dev/null 2>&1 && ldconfig -p 2>/dev/null | grep -q "^[[:space:]]*$_ob_so "; } &&
     ! ls /lib/x86_64-linux-gnu/$_ob_so /usr/lib/x86_64-linux-gnu/$_ob_so /lib64/$_ob_so >/dev/null 2>&1; then
    _ob_ld="$_ob_ld:$_ob_lib/ompi-fallback"; break
  fi
done
export LD_LIBRARY_PATH="$_ob_ld${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
export OMPI_MCA_mca_base_component_show_load_errors=0 OMPI_MCA_btl_vader_single_copy_mechanism=none
# no ssh needed/available: launch locally only
export OMPI_MCA_plm=isolated
# small /dev/shm (docker default 64M) cannot hold 16 vader segments: back them in /tmp
_ob_shm=$(df -Pk /dev/shm 2>/dev/null | awk 'NR==2{print $4}')
if [ ! -w /dev/shm ] || [ "${_ob_shm:-0}" -lt 524288 ]; then
  export OMPI_MCA_btl_vader_backing_directory=/tmp
fi
MPIRUN="$OMPI_BUNDLE/usr/bin/mpirun --allow-run-as-root --oversubscribe --bind-to none --mca plm isolated --mca btl self,vader --mca pml ob1 --mca mtl ^ofi,psm,psm2 --mca osc ^ucx,pt2pt --mca btl_vader_single_copy_mechanism none --mca mca_base_component_show_load_errors 0"
export MPIRUN
unset _ob_lib _ob_px _ob_ld _ob_so _ob_shm
