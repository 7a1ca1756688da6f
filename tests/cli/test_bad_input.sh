# Bad input of every kind: a clear message naming the file and the problem,
# the documented exit code, no crash and no partial output file.
source "$(dirname "$0")/lib.sh"

printf 'x y z mass\n0 0 0 1\n1 1 1 2\n' >good.txt
printf 'x y z mass\n0 0 0 1\n1 1 1\n' >short.txt
printf 'x y z mass\n0 0 0 1\n1 one 1 2\n' >word.txt
printf 'x y z mass\n0 0 0 1\nnan 1 1 2\n3 inf 1 4\n' >nan.txt

write_scene good.yaml good.txt
write_scene short.yaml short.txt
write_scene word.yaml word.txt
write_scene nan.yaml nan.txt
write_scene missing.yaml does-not-exist.txt
write_scene dirinput.yaml .
printf 'input:\n  file: good.txt\ncamera:\n  fvo: 3\n' >unknown-key.yaml
printf 'input:\n  file: good.txt\nimage:\n  width: wide\n' >wrong-type.yaml
printf 'input:\n  file: good.txt\nimage: [1, 2\n' >syntax.yaml

expect_fail 1 "does-not-exist.txt: cannot open: No such file" out -- render missing.yaml
expect_fail 1 "short.txt:3: row has 3 values; the header \(line 1\) names 4 columns" out -- render short.yaml
expect_fail 1 "word.txt:3: column 'y': 'one' is not a number" out -- render word.yaml
expect_fail 1 "nan.txt: particle 1 \(id 1\) has a non-finite position \(nan, 1, 1\); .*input.nonfinite: skip" out -- render nan.yaml
# A non-finite weight is told as the weight, not the (finite) position.
printf 'x y z mass lum\n0 0 0 1 1\n1 2 3 1 nan\n' >nanweight.txt
write_scene nanweight.yaml nanweight.txt
expect_fail 1 "nanweight.txt: particle 1 \(id 1\) has a non-finite weight \(nan\); " out -- \
  render nanweight.yaml --set input.weight=lum
expect_fail 1 "read error: Is a directory" out -- render dirinput.yaml
expect_fail 2 "unknown-key.yaml:4.*camera.fvo" out -- render unknown-key.yaml
expect_fail 2 "wrong-type.yaml:4.*image.width.*wide" out -- render wrong-type.yaml
expect_fail 2 "syntax.yaml:.*YAML" out -- render syntax.yaml
expect_fail 2 "image.width.*out of range" out -- render good.yaml --set image.width=0
expect_fail 2 "image.height.*out of range" out -- render good.yaml --set image.height=-3
expect_fail 1 "no-such-scene.yaml: cannot open scene file" out -- render no-such-scene.yaml
expect_fail 2 "unknown option '--bogus'" out -- render good.yaml --bogus
expect_fail 2 "no scene file given" out -- render
expect_fail 2 "unknown command 'paint'" out -- paint
expect_fail 1 "does-not-exist.txt: cannot open" out -- info does-not-exist.txt

# A reader's error met while smoothing lengths are computed is the
# reader's: no "smoothing lengths from the neighbours" in front of it.
write_scene word-sph.yaml word.txt "deposit: sph" "smoothing:" "  lengths: neighbours"
expect_fail 1 "^orrery: error: word.txt:3: column 'y': 'one' is not a number" out -- render word-sph.yaml
grep -q "smoothing lengths" stderr && fail "a table's syntax error is told as a smoothing-lengths error: $(cat stderr)"

# A UTF-8 byte-order mark is not part of the first column's name.
printf '\xef\xbb\xbfx y z mass\n0 0 0 1\n1 1 1 2\n' >bom.txt
"$ORRERY" info bom.txt >stdout 2>stderr || fail "info of a table with a BOM failed: $(cat stderr)"
grep -q "^fields:     x y z mass$" stdout || fail "info of a table with a BOM: $(cat stdout)"

# A NaN count is not a number (not a huge negative one, nor out of range).
expect_fail 2 "animation.frames: expected an integer, got '.nan', which is not a number" out -- \
  render good.yaml --set animation.frames=.nan
expect_fail 2 "^orrery: error: --particles nan: not a number; expected a whole number" out -- model -o out/m.txt --particles nan
# An output name with a control character: a YAML block scalar's newline
# made files named "abc\n.fits"; a tab typed in --set.
printf 'input:\n  file: good.txt\noutput:\n  dir: out\n  name: |\n    abc\n' >newline-name.yaml
expect_fail 2 "newline-name.yaml:5: output.name: a file name without control characters is needed, but character 4 of 4 is byte 0x0a \(a newline" \
  out -- render newline-name.yaml
expect_fail 2 "output.name: a file name without control characters is needed, but character 2 of 3 is byte 0x09$" out -- \
  render good.yaml --set "output.name=$(printf 'a\tb')"
# camera.dome's hint is about dome profiles, not output.dir.
expect_fail 2 "camera.dome: 'domes/flat-180' must be a file name, without '/' \(a dome profile's name" out -- \
  render good.yaml --set camera.dome=domes/flat-180

# A write that fails for want of space says so, FITS included (cfitsio
# itself says only "error writing to FITS file"). A file-size limit, with
# SIGXFSZ ignored, makes writes fail with EFBIG without a full disk.
(trap '' XFSZ; ulimit -f 64; "$ORRERY" render good.yaml --set image.width=512 --set image.height=512 >stdout 2>stderr)
grep -q "out/good.fits: cannot write FITS file: File too large" stderr || fail "file-size limit: $(cat stderr)"
[ -z "$(ls -A out 2>/dev/null)" ] || fail "file-size limit left files: $(ls -A out)"
# orrery ics's HDF5 snapshot under the same limit: the error, exit 1 (not
# a crash at exit in HDF5), no file and no temporary.
mkdir -p icsout
(trap '' XFSZ; ulimit -f 64; "$ORRERY" ics --zeldovich --grid 16 -o icsout/box.hdf5 >stdout 2>stderr; echo $? >rc)
[ "$(cat rc)" = 1 ] || fail "ics under a file-size limit exited $(cat rc): $(cat stderr)"
grep -q "^orrery: error: icsout/box.hdf5: could not write the HDF5 snapshot: File too large$" stderr ||
  fail "ics under a file-size limit: $(cat stderr)"
[ -z "$(ls -A icsout)" ] || fail "ics under a file-size limit left files: $(ls -A icsout)"
# Under an address-space limit of 400 MB the command starts and renders a
# PNG: OpenImageIO, whose libraries' static initialisers start threads (and
# aborted even --version here), is loaded only for its own formats. Not
# under the sanitizers, whose shadow memory needs terabytes of addresses.
if ! grep -q "ORRERY_SANITIZE:BOOL=ON" "$(dirname "$ORRERY")/CMakeCache.txt" 2>/dev/null; then
  (ulimit -v 400000; "$ORRERY" --version >stdout 2>stderr) || fail "--version under ulimit -v 400000: $(cat stderr)"
  grep -q "^orrery " stdout || fail "--version under ulimit -v 400000 printed: $(cat stdout)"
  (ulimit -v 400000; "$ORRERY" render -q good.yaml -o vlimit >stdout 2>stderr) ||
    fail "render under ulimit -v 400000: $(cat stderr)"
  [ -f vlimit/good.png ] || fail "render under ulimit -v 400000 wrote no PNG: $(ls vlimit)"
fi
# A full file system, where one can be mounted (as root): "No space left on device".
mkdir -p tiny
if mount -t tmpfs -o size=8k tmpfs tiny 2>/dev/null; then
  expect_fail 1 "tiny/good.fits: cannot write FITS file: No space left on device" tiny -- render good.yaml -o tiny
  umount tiny
  # orrery ics's HDF5 snapshot (4096 particles, 121 kB) on a disk too small
  # for its header (HDF5 then crashed at exit) or for its data (the last
  # datasets' writes failed in their close, unseen: exit 0, zeros in the file).
  for size in 8k 64k; do
    mount -t tmpfs -o size=$size tmpfs tiny
    expect_fail 1 "^orrery: error: tiny/box.hdf5: could not write the HDF5 snapshot: No space left on device$" tiny -- \
      ics --zeldovich --grid 16 -o tiny/box.hdf5
    umount tiny
  done
else
  echo "note: cannot mount a small tmpfs here (not root?): the full-disk case is checked with the file-size limit only"
fi

# Options as other GNU tools take them: --output=DIR, -oDIR, "--" before
# an operand; errors in the one-line form of docs/cli.md.
"$ORRERY" render -q --output=eq good.yaml && [ -f eq/good.png ] || fail "--output=DIR did not write eq/good.png"
"$ORRERY" render -q -ojoined good.yaml && [ -f joined/good.png ] || fail "-oDIR did not write joined/good.png"
"$ORRERY" render -q -o dashes -- good.yaml && [ -f dashes/good.png ] || fail "-- before the scene did not work"
"$ORRERY" render good.yaml --set=output.name=viaeq -q && [ -f out/viaeq.png ] || fail "--set=KEY=VALUE did not work"
rm -rf out/viaeq.* eq joined dashes
for cmd in render compose info model ics path video; do
  expect_fail 2 "^orrery: error: unknown option '--bogus' \(see 'orrery $cmd --help'\)$" out -- $cmd --bogus
  [ "$(wc -l <stderr)" -eq 1 ] || fail "$cmd --bogus: more than one line: $(cat stderr)"
  "$ORRERY" $cmd --help >stdout 2>stderr || fail "$cmd --help failed: $(cat stderr)"
  grep -q "^usage: orrery $cmd" stdout || fail "$cmd --help: no usage line: $(cat stdout)"
done
expect_fail 2 "^orrery: error: option '--set' needs a value \(see 'orrery render --help'\)$" out -- render good.yaml --set
expect_fail 2 "^orrery: error: option '--quiet' takes no value" out -- render good.yaml --quiet=yes
expect_fail 2 "^orrery: error: unknown option '-x'" out -- render good.yaml -qx
expect_fail 2 "one scene file at a time \(got 'good.yaml' and '-q'\)" out -- render -- good.yaml -q

# An output folder that cannot be made (its parent is a regular file).
touch plainfile
expect_fail 1 "plainfile/out" plainfile-out -- render good.yaml -o plainfile/out

# orrery compose reads the raw planes from the output folder: one that is
# not there is an error, not made empty (it was, with cfitsio's generic
# message); a raw-planes file that is a FIFO (it hung), a link to
# /dev/zero (it hung) or tile-compressed (fpack) is refused by name.
expect_fail 1 "^orrery: error: missing/dir: no such folder: compose reads the planes" none -- compose good.yaml -o missing/dir
[ -e missing ] && fail "compose -o missing/dir made folders: $(find missing)"
mkdir -p emptydir
expect_fail 1 "emptydir/good.raw.fits: no such file: compose reads the raw planes that .orrery render. writes with output.raw: true" \
  emptydir -- compose good.yaml -o emptydir
mkdir -p fifodir zerodir packdir
mkfifo fifodir/good.raw.fits
ln -s /dev/zero zerodir/good.raw.fits
expect_fail 2 "fifodir/good.raw.fits: a pipe or FIFO; orrery reads its planes from a regular FITS file" none -- \
  compose good.yaml -o fifodir
expect_fail 2 "zerodir/good.raw.fits: a character device; orrery reads its planes from a regular FITS file" none -- \
  compose good.yaml -o zerodir
"$ORRERY" render -q good.yaml -o packdir --set output.raw=true || fail "render with output.raw"
if "$py" -c "
from astropy.io import fits
d = fits.getdata('packdir/good.raw.fits')
fits.HDUList([fits.PrimaryHDU(), fits.CompImageHDU(d)]).writeto('packdir/good.raw.fits', overwrite=True)" 2>/dev/null; then
  expect_fail 1 "packdir/good.raw.fits: HDU 2 is a tile-compressed image; orrery reads its planes uncompressed" none -- \
    compose good.yaml -o packdir
else
  echo "note: no astropy: the tile-compressed raw planes are not checked here (test_fits checks the reader)"
fi

# Skipping non-finite particles is the documented alternative: it succeeds
# and reports how many were left out.
"$ORRERY" render nan.yaml --set input.nonfinite=skip >stdout 2>stderr || fail "skip run failed: $(cat stderr)"
grep -q "skipped 2 non-finite" stdout || fail "skip run does not report 2 skipped: $(cat stdout)"
[ -f out/nan.fits ] && [ -f out/nan.png ] || fail "skip run did not write out/nan.fits and out/nan.png"
ls -A out | grep -q tmp && fail "temporary files left in out: $(ls -A out)"

finish
