"""What the examples share: where the shared reference data are, and how a
rendered image becomes a PNG (Pillow)."""
import argparse
import os

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))


def arguments(description):
    """--data (the shared reference data: $ORRERY_SHARED_DATA, or shared/data
    beside the checkout) and --out (where the picture goes)."""
    default = os.environ.get("ORRERY_SHARED_DATA") or os.path.join(HERE, "..", "..", "..", "shared", "data")
    p = argparse.ArgumentParser(description=description)
    p.add_argument("--data", default=default, help="the shared reference data folder")
    p.add_argument("--out", default=".", help="folder for the picture")
    return p.parse_args()


def save_png(image, path):
    """The graded picture (sRGB floats in [0, 1], row 0 at the top) as 8-bit PNG."""
    from PIL import Image as PILImage

    rgb = np.clip(image.rgb * 255 + 0.5, 0, 255).astype(np.uint8)
    PILImage.fromarray(rgb).save(path)
    print(f"wrote {path}: {image}")
