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


def read_exr(path):
    """An EXR's spec and its channels by name, as float arrays, read with
    OpenImageIO (imported here: only the EXR checks need it)."""
    import OpenImageIO as oiio

    inp = oiio.ImageInput.open(path)
    spec = inp.spec()
    pixels = inp.read_image(oiio.FLOAT)
    inp.close()
    return spec, {name: pixels[:, :, k] for k, name in enumerate(spec.channelnames)}
