#!/usr/bin/env bash
# Installs the Debian packages orrery needs to build, test and run.
# Idempotent: prints nothing and touches nothing when everything is there.
set -euo pipefail

packages=(
  build-essential cmake pkg-config   # compiler and build
  libcfitsio-dev                     # FITS output
  libpng-dev zlib1g-dev              # PNG output
  libyaml-dev                        # scene files
  libhdf5-dev                        # Gadget/SWIFT/AREPO HDF5 snapshots
  libfftw3-dev                       # convolution (Gaussian and PSF)
  libopenexr-dev                     # OpenEXR output, through its C API (OpenEXRCore 3.1)
  libopenimageio-dev                 # TIFF, JPEG, ... output and image reading (OpenImageIO 2.4, C++)
  libchealpix-dev                    # the healpix projection: HEALPix's pixel search (chealpix)
  libgomp1                           # OpenMP runtime (gcc's)
  libopenmpi-dev openmpi-bin         # orrery-mpi: rendering on MPI ranks (optional at configure time)
  clang libclang-rt-dev libomp-dev   # libFuzzer for the reader fuzz targets (clang build)
  python3-astropy python3-numpy      # tests: an independent FITS WCS reader; the Python package (numpy)
  python3-pytest                     # tests: the Python package's tests (tests/python)
  python3-h5py python3-yt            # examples/python and their tests: snapshots read with h5py and yt
  python3-pil                        # tests: an independent PNG reader (Pillow)
  fitsverify                         # tests: NASA's FITS checker on the FITS outputs
  python3-openimageio                # tests: OpenImageIO's Python bindings read the EXR back as a compositor would
  python3-healpy                     # tests: healpy reads the HEALPix maps
  python3-scipy                      # tests and scripts: check_star_glide.py (local maxima), box_stats.py (growth ODE)
  python3-yaml                       # tests: PyYAML parses the scene stored in FITS and the README's scenes; the package reads a scene file's units
  python3-pip python3-venv           # pip install . into a virtual environment (tests/python/test_install.py)
  splash                             # tests and benchmark: SPLASH, the reference SPH renderer
  ffmpeg                             # orrery video: encodes frame sequences (ffmpeg; ffprobe for its tests)
  locales                            # tests: localedef makes the ','-decimal locale of test_locale
  procps                             # tests: pgrep finds the MPI rank the N-body tests kill
  strace                             # tests: scripts/measure-mpi-reads.sh counts each MPI rank's reads with it
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done
[ ${#missing[@]} -eq 0 ] && exit 0

sudo=""
if [ "$(id -u)" -ne 0 ]; then
  if command -v sudo >/dev/null; then sudo="sudo"; else
    echo "install-deps: these packages are missing and installing them needs root: ${missing[*]}" >&2
    exit 1
  fi
fi
echo "install-deps: installing ${missing[*]}" >&2
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -qq
$sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
