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
expect_fail 1 "nan.txt: particle 1 \(id 1\) has a non-finite position .*input.nonfinite: skip" out -- render nan.yaml
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

# An output folder that cannot be made (its parent is a regular file).
touch plainfile
expect_fail 1 "plainfile/out" plainfile-out -- render good.yaml -o plainfile/out

# Skipping non-finite particles is the documented alternative: it succeeds
# and reports how many were left out.
"$ORRERY" render nan.yaml --set input.nonfinite=skip >stdout 2>stderr || fail "skip run failed: $(cat stderr)"
grep -q "skipped 2 non-finite" stdout || fail "skip run does not report 2 skipped: $(cat stdout)"
[ -f out/nan.fits ] && [ -f out/nan.png ] || fail "skip run did not write out/nan.fits and out/nan.png"
ls -A out | grep -q tmp && fail "temporary files left in out: $(ls -A out)"

finish
