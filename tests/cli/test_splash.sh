# orrery's SPH column-density image against SPLASH (D. Price's SPH renderer,
# Debian package `splash`) rendering the same particles with the same kernel:
# 20000 particles (a Plummer sphere and a dense clump, h from the model's
# density), 256 x 256 pixels over 8 x 8 length units, each of the three
# kernels. In pixels with more than a few particles per kernel the images
# must agree within 1 %: at the same resolution where the kernels are
# resolved (h >= 3 pixels), and, whatever h, against SPLASH rendered 4 x 4
# finer and extrapolated to pixel averages (SPLASH samples the kernel at
# pixel centres; orrery integrates it over the pixel). How SPLASH is driven
# and what differs: docs/splash.md. Skipped (77) without splash or without
# numpy and astropy.
source "$(dirname "$0")/lib.sh"
here=$(cd "$(dirname "$0")" && pwd)

if ! command -v splash >/dev/null 2>&1; then
  echo "SKIP: splash is not installed"
  exit 77
fi
py=/usr/bin/python3
[ -x "$py" ] || py=python3
if ! "$py" -c "import numpy, astropy" 2>/dev/null; then
  echo "SKIP: numpy and astropy are needed"
  exit 77
fi

width=8
npix=256
fine=1024
export OMP_NUM_THREADS=1

"$py" "$here/compare_splash.py" particles particles.txt || { fail "could not write the particles"; finish; }

# SPLASH's settings: save its defaults from the menu (s, then q), then set the
# number of pixels, the kernel, plain (not normalised, not accelerated,
# not exact) column-density rendering. Limits: x and y columns span the view.
printf 's\nq\n' | splash particles.txt >splash-menu.log 2>&1
if [ ! -f splash.defaults ]; then
  fail "splash did not write splash.defaults: $(tail -5 splash-menu.log)"
  finish
fi
set_default() { # KEY VALUE: replace the line ' KEY=...' of splash.defaults
  grep -q "^ $1=" splash.defaults || fail "splash.defaults has no $1"
  sed -i "s/^ $1=.*/ $1=$2,/" splash.defaults
}
set_default INORMALISE_INTERPOLATIONS F
set_default IFASTRENDER F
set_default EXACT_RENDERING F
set_default IDENSITYWEIGHTEDINTERPOLATION F
half=$((width / 2))
printf -- '-%s %s\n-%s %s\n-1000 1000\n0 1\n0 1\n0 1\n' $half $half $half $half >splash.limits

# render_splash KERNEL-NUMBER NPIX OUT.pix: SPLASH's column density of
# column 6 (rho, weight m / (rho h^3): the sum of m F(q) / h^2) in x-y.
render_splash() {
  set_default IKERNEL "$1"
  set_default NPIX "$2"
  rm -f particles.txt_*.pix
  if ! splash -x 1 -y 2 -r 6 -dev /null -o ascii particles.txt >splash.log 2>&1; then
    fail "splash failed: $(tail -5 splash.log)"
    return 1
  fi
  grep -q "projecting: *$2 x *$2" splash.log || { fail "splash did not render $2 x $2: $(grep projecting splash.log)"; return 1; }
  mv particles.txt_*_proj.pix "$3"
}

for spec in cubic:1:"M4 cubic" wendland-c2:4:"Wendland C2" wendland-c4:5:"Wendland C4"; do
  IFS=: read -r kernel number label <<<"$spec"
  render_splash "$number" $npix "splash-$kernel.pix" || continue
  grep -q "Using $label" splash.log || fail "$kernel: splash did not use the $label kernel"
  render_splash "$number" $fine "splash-$kernel-fine.pix" || continue
  cat >"$kernel.yaml" <<EOF
input: {file: particles.txt}
deposit: sph
smoothing: {kernel: $kernel, lengths: file}
camera: {projection: orthographic, width: $width}
image: {width: $npix, height: $npix}
output: {dir: out, name: $kernel, png: false}
EOF
  if ! "$ORRERY" render --quiet "$kernel.yaml" 2>err.txt; then
    fail "$kernel: orrery: $(cat err.txt)"
    continue
  fi
  echo "== $kernel"
  "$py" "$here/compare_splash.py" compare --orrery "out/$kernel.fits" --splash "splash-$kernel.pix" \
    --fine "splash-$kernel-fine.pix" --particles particles.txt --width $width ||
    fail "$kernel: orrery and SPLASH differ by 1 % or more"
done
finish
