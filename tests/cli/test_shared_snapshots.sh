# Every real snapshot in the shared reference data (../shared/data, see its
# README) goes through `orrery info` and `orrery render`: the detected format,
# the particle count and the mass total must be the values that README lists
# (read there with independent readers), and a render that frames the whole
# snapshot must put all of that mass in the image, summed back by astropy.
source "$(dirname "$0")/lib.sh"
DATA=${ORRERY_SHARED_DATA:-$SRC/../shared/data}
if [ ! -d "$DATA" ]; then
  echo "shared data not found at $DATA: skipped"
  exit 77
fi
py=/usr/bin/python3
[ -x "$py" ] || py=python3

# file | format | particles | total mass (README) | centre | camera width
cases=(
  "gadget2/gadget2_examples/galaxy_littleendian.dat|gadget|60000|46.5039423|0|500"
  "gadget2/gadget2_examples/gassphere_littleendian.dat|gadget|1472|1.00000002|0|3"
  "gadget2/gadget2_examples/gassphere_bigendian.dat|gadget|1472|1.00000002|0|3"
  "gadget2/gadgetreader_format2/test_g2_snap|gadget|8192|200.0107394|1500|3200"
  "hdf5/gadget4_lcdm_gas/snapshot_004.hdf5|hdf5|65536|1040812.37|25000|52000"
  "hdf5/swift_robertsflow/g32_randB_withVP.hdf5|hdf5|32768|248.050217|3.14159|6.6"
  "tipsy/king_soft.bin|tipsy|36000|25.0540639|0|60"
  "tipsy/lambs.00200_subsamp_30K|tipsy|30000|0.299792791|0|1.1"
  "tipsy/test4.tbin|tipsy|67495|0.999999971|0|1.1"
  "tipsy/onestar.tbin|tipsy|1089|1.00014771|0|1.1"
)

# close A B: relative difference below 2e-6 (the README's 9 digits, float sums)
close() { awk -v a="$1" -v b="$2" 'BEGIN { d = a - b; if (d < 0) d = -d; exit !(d <= 2e-6 * (b < 0 ? -b : b)) }'; }

for entry in "${cases[@]}"; do
  IFS='|' read -r rel format count mass centre width <<<"$entry"
  file=$DATA/$rel
  name=$(basename "$rel")
  if ! "$ORRERY" info "$file" >info.txt 2>err.txt; then
    fail "info $rel: $(cat err.txt)"
    continue
  fi
  got_format=$(awk '$1 == "format:" { print $2 }' info.txt)
  got_count=$(awk '$1 == "particles:" { print $2 }' info.txt)
  got_mass=$(awk '$1 == "mass:" { print $3 }' info.txt)
  [ "$got_format" = "$format" ] || fail "info $rel: format '$got_format', expected $format"
  [ "$got_count" = "$count" ] || fail "info $rel: $got_count particles, expected $count"
  close "$got_mass" "$mass" || fail "info $rel: mass total $got_mass, expected $mass"

  cat >"$name.yaml" <<EOF
input:
  file: $file
camera:
  projection: orthographic
  width: $width
  look_at: [$centre, $centre, $centre]
  position: [$centre, $centre, $(awk -v c="$centre" -v w="$width" 'BEGIN { print c + 2 * w }')]
image:
  width: 128
  height: 128
deposit: cic
output:
  dir: out
  name: $name
  png: false
EOF
  if ! "$ORRERY" render --quiet "$name.yaml" 2>err.txt; then
    fail "render $rel: $(cat err.txt)"
    continue
  fi
  # Pixels hold mass per unit area: times a pixel's, (width / 128)^2.
  image_mass=$("$py" -c "
import sys, numpy as np
from astropy.io import fits
area = (float(sys.argv[2]) / 128) ** 2
print(repr(float(np.nansum(fits.getdata(sys.argv[1]).astype(np.float64))) * area))" "out/$name.fits" "$width")
  # float32 pixels: the sum agrees to about 1e-6 of the total
  awk -v a="$image_mass" -v b="$mass" 'BEGIN { d = a - b; if (d < 0) d = -d; exit !(d <= 1e-5 * b) }' ||
    fail "render $rel: the image holds mass $image_mass, the snapshot $mass"
done
finish
