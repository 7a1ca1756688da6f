# output.exr_population_layers: each colour population's light as the EXR
# layer NAME.R, NAME.G, NAME.B, NAME.A (tests/cli/check_exr_population_layers.py,
# through OpenImageIO's Python bindings), and the scenes the key is refused for.
source "$(dirname "$0")/lib.sh"

MODEL='input:
  model:
    name: mw-m31
    particles: 2000
image:
  width: 16
  height: 16
'
pops() { # pops NAME...: one population of every star per name
  echo "colour:"
  echo "  populations:"
  for name in "$@"; do
    printf '    - name: "%s"\n      colour: {temperature: 5000}\n      luminance: {mass: 1}\n' "$name"
  done
}
scene() { # scene FILE EXR BODY: the model, BODY, output.exr: EXR and the layers' key
  printf '%s%s\noutput:\n  dir: none\n  exr: %s\n  exr_population_layers: true\n' "$MODEL" "$3" "$2" >"$1"
}

scene no-pops.yaml true ""
expect_fail 2 "output.exr_population_layers: needs colour.populations" none -- render no-pops.yaml

scene no-exr.yaml false "$(pops disc bulge)"
expect_fail 2 "output.exr_population_layers: needs output.exr: true" none -- render no-exr.yaml

for bad in "old.red" "old red" "é"; do
  scene bad.yaml true "$(pops disc "$bad")"
  expect_fail 2 "population '$bad' cannot name the layer $bad\\.R" none -- render bad.yaml
done
for own in xyz extinction; do
  scene own.yaml true "$(pops disc "$own")"
  expect_fail 2 "population '$own' would name its layer as the EXR's own layer $own" none -- render own.yaml
done

scene nine.yaml true "$(pops p1 p2 p3 p4 p5 p6 p7 p8 p9)"
expect_fail 2 "output.exr_population_layers: at most 8 populations, the scene has 9" none -- render nine.yaml

scene stereo.yaml true "$(pops disc bulge)
stereo:
  mode: anaglyph"
expect_fail 2 "output.exr_population_layers: not with stereo.mode anaglyph" none -- render stereo.yaml

python_with OpenImageIO python3-openimageio
"$py" "$(dirname "$0")/check_exr_population_layers.py" "$ORRERY" "$WORK" || fail "EXR population layer checks"
finish
