"""Numbers with units (astropy Quantities, unyt and yt arrays) as plain
numbers in the scene's units: lengths (positions, smoothing lengths) in
output.length_unit, masses (and a field that is the weight) in output.bunit.
A number with a unit the scene has none for, or one that does not convert,
is refused naming both units: numpy would otherwise drop the unit silently
(np.asarray of a Quantity is its value in whatever unit it has)."""
import os

LENGTH_KEY, WEIGHT_KEY = "output.length_unit", "output.bunit"


def _flatten(prefix, value, out):
    """Nested dicts as dotted keys: camera={"fov": 60} is camera.fov."""
    if isinstance(value, dict):
        for k, v in value.items():
            _flatten(f"{prefix}.{k}" if prefix else str(k), v, out)
    else:
        out[prefix] = value


def _scene_keys(scene):
    """The scene's keys, dotted: a dict as it is, a file read as YAML (no
    keys when PyYAML is missing: then the scene states no units)."""
    keys = {}
    if isinstance(scene, dict):
        _flatten("", scene, keys)
        return keys
    try:
        import yaml
    except ImportError:
        return keys
    with open(os.fspath(scene)) as f:
        _flatten("", yaml.safe_load(f) or {}, keys)
    return keys


def scene_units(scene, settings):
    """{"length": unit or None, "weight": unit or None, "weight_name": the
    weight} of a scene (dict or file) with its overrides (dotted keys), as
    FITS unit strings ("kpc", "10**10 solMass")."""
    keys = {**_scene_keys(scene), **settings}
    return {"length": keys.get(LENGTH_KEY) or None, "weight": keys.get(WEIGHT_KEY) or None,
            "weight_name": keys.get("input.weight") or "mass"}


def has_unit(a):
    """An astropy Quantity, or a unyt (yt) array."""
    return hasattr(a, "to_astropy") or (hasattr(a, "unit") and hasattr(a, "to_value"))


def plain(name, a, unit, key):
    """a's numbers in unit (a FITS unit string; None: the scene states none,
    key saying where it would), or a itself when it has no unit."""
    if not has_unit(a):
        return a
    from astropy import units as u

    given = getattr(a, "units", None) or getattr(a, "unit", None)
    try:
        q = a.to_astropy() if hasattr(a, "to_astropy") else a
    except Exception as e:  # a unit astropy has no name for (yt's code units, comoving lengths)
        raise ValueError(f"orrery: {name}: unit {given} has no astropy equivalent ({e}): convert it first, "
                         "e.g. .to('kpc')") from None
    if q.unit == u.dimensionless_unscaled:
        return q.value
    if unit is None:
        raise ValueError(f"orrery: {name}: in {q.unit}, but the scene states no unit for it"
                         + (f" ({key}): set {key}, or pass plain numbers" if key else ": pass plain numbers"))
    try:
        return q.to_value(u.Unit(unit, format="fits"))
    except u.UnitConversionError:
        raise ValueError(f"orrery: {name}: in {q.unit}, which does not convert to the scene's {unit} "
                         f"({key})") from None


def convert(units, positions, masses, h, fields, velocities, time):
    """The render's arguments, numbers with units as plain numbers in the
    scene's units (or refused)."""
    length, weight = units["length"], units["weight"]
    if isinstance(positions, (tuple, list)) and len(positions) == 3 and any(has_unit(c) for c in positions):
        positions = tuple(plain(f"positions[{k}]", c, length, LENGTH_KEY) for k, c in enumerate(positions))
    else:
        positions = plain("positions", positions, length, LENGTH_KEY)
    weighs_mass = units["weight_name"] == "mass"
    masses = plain("masses", masses, weight if weighs_mass else None, WEIGHT_KEY if weighs_mass else None)
    h = plain("h", h, length, LENGTH_KEY) if h is not None else None
    fields = {name: plain(f"fields[{name!r}]", a, weight if name == units["weight_name"] else None,
                          WEIGHT_KEY if name == units["weight_name"] else None)
              for name, a in dict(fields or {}).items()}
    if velocities is not None:
        velocities = plain("velocities", velocities, None, None)  # orrery has no velocity unit
    time = plain("time", time, None, None)  # nor a time unit
    return positions, masses, h, fields, velocities, time
