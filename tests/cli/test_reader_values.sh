# Values every reader refuses the same way (docs/input.md): a NaN or
# infinite snapshot time (it would fail every render at the FITS write), and
# masses that are negative, non-finite or cannot be held by a float. The
# files are made by make_snapshot.py beside this script.
source "$(dirname "$0")/lib.sh"
py=/usr/bin/python3
[ -x "$py" ] || py=python3
make() { "$py" "$SRC/tests/cli/make_snapshot.py" "$@" || fail "make_snapshot.py $*"; }

# A NaN or infinite time: refused by `orrery info`, naming the header field.
make gadget nantime.gdt --time nan
make tipsy inftime.bin --time inf
expect_fail 1 "nantime.gdt: header time = nan is not a finite number" out -- info nantime.gdt
expect_fail 1 "inftime.bin: header time = inf is not a finite number" out -- info inftime.bin --format tipsy
write_scene nantime.yaml nantime.gdt
expect_fail 1 "nantime.gdt: header time = nan is not a finite number" out -- render nantime.yaml

# Masses: the same policy in every reader, whatever input.nonfinite says.
make gadget negative.gdt --masses 1,-2,1
make gadget nanmass.gdt --masses 1,nan,1
make gadget tiny.gdt --masses 1,1e-300,1 --double
make tipsy negative.bin --masses 1,1,-1.5
printf 'x y z mass\n0 0 0 1\n1 0 0 1e-300\n' >tiny.txt
for f in negative.gdt nanmass.gdt tiny.gdt negative.bin tiny.txt; do write_scene "${f%.*}-${f#*.}.yaml" "$f"; done
expect_fail 1 "negative.gdt: block MASS: particle 1 of the file \(type 0\): mass -2 is negative" out -- render negative-gdt.yaml
expect_fail 1 "nanmass.gdt: block MASS: particle 1 of the file \(type 0\): mass nan is not a finite number" out -- \
  render nanmass-gdt.yaml --set input.nonfinite=skip
expect_fail 1 "tiny.gdt: block MASS: particle 1 of the file \(type 0\): mass 1e-300 is too small for a float" out -- \
  render tiny-gdt.yaml
expect_fail 1 "negative.bin: dark particle 2 \(particle 2 of the file\): mass -1.5 is negative" out -- render negative-bin.yaml
expect_fail 1 "tiny.txt:3: column 'mass': particle 1: mass 1e-300 is too small for a float" out -- render tiny-txt.yaml
expect_fail 1 "negative.gdt: block MASS: particle 1 of the file \(type 0\): mass -2 is negative" out -- info negative.gdt

# The generator's good files read: 0 and a float subnormal are masses.
make gadget good.gdt --masses 1,0,1e-40 --double
make tipsy good.bin --masses 1,0,2
for f in good.gdt good.bin; do
  "$ORRERY" info "$f" >info.txt 2>err.txt || fail "info $f: $(cat err.txt)"
  grep -q "time: *0.5" info.txt || fail "info $f: no time 0.5: $(cat info.txt)"
done

finish
