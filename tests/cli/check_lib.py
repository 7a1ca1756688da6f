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


def blender_pass(name):
    """How Blender's multilayer OpenEXR reader (3.4, imbuf's
    imb_exr_split_channel_name) files a channel: (layer, pass, channel id),
    or None where it drops the channel. A one-letter name is a pass of the
    unnamed layer (R, G, B, A the Combined pass); otherwise, split at the
    dots from the end: the channel (one letter, two letters whose second is
    one of XYZRGBUVA, or red, green, blue, alpha, depth), the pass, then the
    layer (all the rest, maybe empty). Written from the reader's rules, to
    check names without Blender at hand."""
    if len(name) == 1:
        return "", "Combined" if name in "RGBA" else name, name.upper()
    head, dot, channel = name.rpartition(".")
    if not dot or not channel:
        return None
    if len(channel) == 2 and channel[1].upper() in "XYZRGBUVA":
        chan_id = channel[1].upper()
    elif len(channel) == 1:
        chan_id = channel.upper()
    else:
        chan_id = {"red": "R", "green": "G", "blue": "B", "alpha": "A", "depth": "Z"}.get(channel.lower())
    if chan_id is None:
        return None
    layer, _, pass_name = head.rpartition(".")
    return (layer, pass_name, chan_id) if pass_name else None


def read_exr(path):
    """An EXR's spec and its channels by name, as float arrays, read with
    OpenImageIO (imported here: only the EXR checks need it)."""
    import OpenImageIO as oiio

    inp = oiio.ImageInput.open(path)
    spec = inp.spec()
    pixels = inp.read_image(oiio.FLOAT)
    inp.close()
    return spec, {name: pixels[:, :, k] for k, name in enumerate(spec.channelnames)}
