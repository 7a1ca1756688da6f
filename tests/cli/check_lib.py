"""What the check_*.py scripts share: the command line (ORRERY WORKDIR) and
a tally of failed expectations that says what failed and sets the exit
status."""
import sys


class Checks:
    def __init__(self):
        self.orrery, self.work = sys.argv[1], sys.argv[2]
        self.failures = 0

    def __call__(self, ok, what):
        """Counts and prints what as a failure unless ok."""
        if not ok:
            print("FAIL:", what)
            self.failures += 1

    def finish(self, name):
        print(f"{name}:", "failed" if self.failures else "passed")
        sys.exit(1 if self.failures else 0)


def colour_dome_scene(size, output):
    """A small colour dome master of the built-in model (20000 particles,
    one population of 5000 K stars), size x size pixels, with the given
    lines under output: (each indented by two spaces, ending in a newline)."""
    return ("input:\n  model:\n    name: mw-m31\n    particles: 20000\n  types: [2, 3]\n"
            "camera:\n  projection: dome\n  position: [-30, 0, 10]\n  look_at: [0, 0, 0]\n"
            f"image:\n  width: {size}\n  height: {size}\n"
            "colour:\n  populations:\n    - name: stars\n      select: {types: [2, 3]}\n"
            "      colour: {temperature: 5000}\n      luminance: {mass: 1}\n"
            "output:\n" + output)


def read_exr(path):
    """An EXR's spec and its channels by name, as float arrays, read with
    OpenImageIO (imported here: only the EXR checks need it)."""
    import OpenImageIO as oiio

    inp = oiio.ImageInput.open(path)
    spec = inp.spec()
    pixels = inp.read_image(oiio.FLOAT)
    inp.close()
    return spec, {name: pixels[:, :, k] for k, name in enumerate(spec.channelnames)}
