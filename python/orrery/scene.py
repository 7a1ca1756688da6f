"""orrery.Scene: a scene loaded once, rendered from numpy arrays."""
import ctypes
import json
import operator
import os
import tempfile
import threading

import numpy as np

from . import _arrays, _units
from ._lib import PROGRESS_FN, lib
from ._units import _flatten


class OrreryError(Exception):
    """An error liborrery reported; str() is its message, naming the scene
    key, array or file. .code is the status (orrery.h's ORRERY_ERR_*)."""

    def __init__(self, message, code):
        super().__init__(message)
        self.code = code


class Cancelled(BaseException):
    """A render stopped by its progress callback returning False: nothing
    was written and no image is returned. A BaseException, as
    KeyboardInterrupt and asyncio.CancelledError are, so that an
    `except Exception` meant for bad input does not swallow the stop."""


LONG_MAX = 2 ** (8 * ctypes.sizeof(ctypes.c_long) - 1) - 1  # orrery_render's frame is a C long


def _frame_number(frame):
    """frame as orrery_render takes it: an integer in 0..LONG_MAX (ctypes
    would wrap a larger one to a negative number)."""
    try:
        frame = operator.index(frame)
    except TypeError:
        raise TypeError(f"orrery: frame: {frame!r} is not an integer") from None
    if not 0 <= frame <= LONG_MAX:
        raise ValueError(f"orrery: frame: {frame} is outside 0..{LONG_MAX}")
    return frame


# Output keys turned off when a scene renders to memory only.
_NO_FILES = {"output.fits": False, "output.png": False, "output.exr": False, "output.raw": False}


def _override_text(key, value):
    """One "key=value" as `orrery render --set` takes it (YAML flow text;
    JSON is a subset of it)."""
    if isinstance(value, np.generic):
        value = value.item()
    if isinstance(value, np.ndarray):
        value = value.tolist()
    return f"{key}={json.dumps(value)}"


def _card_value(text):
    """A FITS-style card value from orrery_image_header's text."""
    if text.startswith("'"):
        return text[1:-1].replace("''", "'")
    if text in ("T", "F"):
        return text == "T"
    try:
        return int(text)
    except ValueError:
        return float(text)


def parse_header(text):
    """orrery_image_header's text as a dict, in card order."""
    cards = {}
    for line in text.splitlines():
        key, _, value = line.partition(" = ")
        cards[key] = _card_value(value)
    return cards


def _top_down_wcs(cards, height):
    """The cards with the WCS of the array as returned, row 0 at the top.
    orrery's FITS files store rows bottom-up, as FITS counts them: the
    array's row r is the file's row height - r, so the reference pixel's row
    is mirrored and pixel axis 2 runs the other way (the CD matrix's, or PC
    matrix's, second column negated; with neither, CDELT2)."""
    if "CRPIX2" not in cards:
        return cards  # no WCS (a HEALPix map, or a view no standard WCS describes)
    cards = dict(cards)
    cards["CRPIX2"] = height + 1 - cards["CRPIX2"]
    if any(k in cards for k in ("CD1_1", "CD1_2", "CD2_1", "CD2_2")):
        for key in ("CD1_2", "CD2_2"):
            cards[key] = -cards.get(key, 0.0)
    elif any(k in cards for k in ("PC1_1", "PC1_2", "PC2_1", "PC2_2")):
        cards["PC1_2"], cards["PC2_2"] = -cards.get("PC1_2", 0.0), -cards.get("PC2_2", 1.0)
    else:
        cards["CDELT2"] = -cards.get("CDELT2", 1.0)
    return cards


def _header(cards):
    """An astropy.io.fits.Header of the cards when astropy is there, else the dict."""
    try:
        from astropy.io import fits
    except ImportError:
        return cards
    header = fits.Header(list(cards.items()))
    if "CRPIX2" in cards:
        header.add_comment("WCS of the array as returned: rows top-down (the FITS file's are bottom-up)")
    return header


class Image:
    """One view's render: .planes maps each plane's name ("mass", or "X",
    "Y", "Z" with colour) to a (height, width) float32 array, row 0 at the
    top (a FITS file stores rows bottom-up: np.flipud of its data); .rgb is
    the graded picture, (height, width, 3) sRGB values in [0, 1]; .header the
    FITS cards (an astropy.io.fits.Header, or a dict without astropy), whose
    WCS describes .data as returned (rows top-down); .wcs that WCS as an
    astropy.wcs.WCS; .units each plane's unit (BUNIT)."""

    def __init__(self, planes, units, rgb, header):
        self.planes, self.units, self.rgb, self.header = planes, units, rgb, header

    @property
    def data(self):
        """The first plane: the weight, or X with colour."""
        return next(iter(self.planes.values()))

    @property
    def wcs(self):
        """The header's WCS as an astropy.wcs.WCS of .data (needs astropy);
        None for a view without one."""
        from astropy.wcs import WCS

        return WCS(self.header) if "CTYPE1" in self.header else None

    def __repr__(self):
        if self.data.ndim == 1:
            return f"<orrery.Image HEALPix nside {self.header['NSIDE']} planes {list(self.planes)}>"
        h, w = self.data.shape
        return f"<orrery.Image {w}x{h} planes {list(self.planes)}>"


def _copy_floats(pointer, shape):
    """A numpy copy of floats the library owns until its next render."""
    count = int(np.prod(shape))
    return np.ctypeslib.as_array(pointer, shape=(count,)).reshape(shape).copy()


class Scene:
    """A scene (a YAML file's path, or a dict of its keys) ready to render
    numpy arrays. Keyword arguments override its keys: nested dicts
    (camera={"fov": 60}), or dotted keys in overrides={"camera.fov": 60}.
    With write=False (the default) nothing is written to disk: the images
    come back as arrays only. With write=True the scene's own outputs are
    written too (output.dir, output.name) and listed in scene.outputs."""

    def __init__(self, scene, overrides=None, write=False, **kwargs):
        # Held for each render and for close: the renderer is never used by
        # two threads at once nor freed under a render.
        self._lock = threading.Lock()
        self._rendering_thread = None
        self._r = ctypes.c_void_p()
        settings = {}
        _flatten("", dict(overrides or {}), settings)
        _flatten("", kwargs, settings)
        if not write:
            settings = {**_NO_FILES, "output.dir": tempfile.gettempdir(), **settings}
        texts = [_override_text(k, v).encode() for k, v in settings.items()]
        argv = (ctypes.c_char_p * max(len(texts), 1))(*texts)
        msg = ctypes.create_string_buffer(2048)
        if isinstance(scene, dict):
            base = os.getcwd().encode()
            st = lib.orrery_open_yaml(ctypes.byref(self._r), json.dumps(scene).encode(), base, argv, len(texts),
                                      msg, len(msg))
        else:
            st = lib.orrery_open(ctypes.byref(self._r), os.fspath(scene).encode(), argv, len(texts), msg, len(msg))
        if st != 0:
            raise OrreryError(msg.value.decode(errors="replace"), st)
        lib.orrery_keep_images(self._r, 1)
        # The scene's units, which numbers with units are converted to.
        self.units = _units.scene_units(scene, settings)
        self.outputs = []
        self.seconds = 0.0

    def close(self):
        """Frees the renderer; a render running in another thread is waited
        for. Rendering afterwards raises OrreryError."""
        if self._rendering_thread == threading.get_ident():
            raise OrreryError("orrery: Scene.close: not from the scene's own render (its progress callback)", 2)
        with self._lock:
            if self._r:
                lib.orrery_close(self._r)
                self._r = ctypes.c_void_p()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def __del__(self):
        self.close()

    def render(self, positions, masses=1.0, ids=None, h=None, fields=None, time=0.0, types=None,
               velocities=None, frame=0, progress=None):
        """Renders every view of the scene from these particles and returns
        a list of Image, one per view (two for a stereo view: left, right).

        positions: (N, 3) float32/float64 (any strides) or three (N,) arrays;
        masses: (N,) or one number for all; ids: (N,) integers (absent:
        0..N-1); h: smoothing lengths (support 2h); fields: {name: (N,)},
        at most 8, usable as input.weight and by colour populations; types:
        Gadget types 0..5; velocities: (N, 3), the fields vx, vy, vz; time:
        the simulation time; frame: the frame of the scene's animation
        (camera paths move with it). The arrays are read in place during the
        call (the GIL is released meanwhile) and not kept. Numbers with
        units (astropy, unyt) are converted to scene.units: lengths to
        output.length_unit, masses to output.bunit; refused (ValueError
        naming the unit) where the scene states none. progress(done, total)
        is called between chunks of particles (in this thread). When it
        returns False (not None) the render stops before its next chunk and
        raises orrery.Cancelled; when it raises, the render stops the same
        way and its exception is raised. A stopped render writes no file
        and returns no image; the Scene renders again as usual.

        One Scene renders one thing at a time: a render started while it
        renders in another thread raises OrreryError (a Scene per thread
        renders in parallel)."""
        if not self._lock.acquire(blocking=False):
            raise OrreryError("orrery: Scene.render: this Scene is already rendering in another thread "
                              "(use one Scene per thread)", 2)
        self._rendering_thread = threading.get_ident()
        try:
            return self._render(positions, masses, ids, h, fields, time, types, velocities, frame, progress)
        finally:
            self._rendering_thread = None
            self._lock.release()

    def _render(self, positions, masses, ids, h, fields, time, types, velocities, frame, progress):
        if not self._r:
            raise OrreryError("orrery: Scene.render: the scene is closed", 2)
        frame = _frame_number(frame)
        positions, masses, h, fields, velocities, time = _units.convert(self.units, positions, masses, h, fields,
                                                                        velocities, time)
        arrays = _arrays.describe(positions, masses, ids, h, fields, types, velocities, time)
        raised = []

        def report(user, done, total):
            if raised:
                return
            try:
                if progress(done, total) is False:
                    raised.append(Cancelled(f"orrery: the progress callback stopped the render after {done} "
                                            f"of {total} particles"))
            except BaseException as e:  # not through C: raised when the render returns
                raised.append(e)
            if raised:
                lib.orrery_cancel(self._r)  # stops before the next chunk

        callback = PROGRESS_FN(report) if progress else ctypes.cast(None, PROGRESS_FN)
        lib.orrery_set_progress(self._r, callback, None)
        try:
            st = lib.orrery_render(self._r, ctypes.byref(arrays.c), frame)
        finally:
            lib.orrery_set_progress(self._r, ctypes.cast(None, PROGRESS_FN), None)
        if raised:  # the render stopped (CANCELLED) at the chunk after the callback's
            raise raised[0]
        if st != 0:
            raise OrreryError(lib.orrery_error(self._r).decode(errors="replace"), st)
        self.outputs = [lib.orrery_output(self._r, i).decode() for i in range(lib.orrery_output_count(self._r))]
        self.seconds = lib.orrery_render_seconds(self._r)
        return [self._image(i) for i in range(lib.orrery_image_count(self._r))]

    def _image(self, i):
        w, h, n = ctypes.c_int(), ctypes.c_int(), ctypes.c_int()
        lib.orrery_image_size(self._r, i, ctypes.byref(w), ctypes.byref(h), ctypes.byref(n))
        cards = parse_header(lib.orrery_image_header(self._r, i).decode())
        # A HEALPix map is a table of pixels in pixel order (RING or NESTED,
        # as the FITS file's rows): one value per pixel, as healpy takes it.
        shape = (w.value * h.value,) if cards.get("PIXTYPE") == "HEALPIX" else (h.value, w.value)
        planes, units = {}, {}
        for j in range(n.value):
            name, unit = ctypes.c_char_p(), ctypes.c_char_p()
            data = lib.orrery_image_plane(self._r, i, j, ctypes.byref(name), ctypes.byref(unit))
            planes[name.value.decode()] = _copy_floats(data, shape)
            units[name.value.decode()] = unit.value.decode()
        rgb = lib.orrery_image_rgb(self._r, i)
        rgb = _copy_floats(rgb, shape + (3,)) if rgb else None
        return Image(planes, units, rgb, _header(_top_down_wcs(cards, h.value)))


def render(scene, positions, masses=1.0, **kwargs):
    """One render of a scene, the first view's Image: Scene(scene).render(...)[0]."""
    with Scene(scene) as s:
        return s.render(positions, masses, **kwargs)[0]
