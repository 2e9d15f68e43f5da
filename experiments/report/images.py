"""The run's images: PNGs embedded as data URIs, and the linear float data the
interactive viewer flips through.

The viewer wants linear radiance so that its exposure slider means something
above 1. That comes from the run's EXRs through the `lightbench` Python module
(read_exr); without the module, or without the reference's EXR, every image of
the scene falls back to its 8-bit sRGB PNG, decoded back to linear: values
above 1 were clipped by the PNG writer and stay clipped. A scene's images are
all EXR or all PNG, so that a flip never compares clipped with unclipped data.
"""
import base64
import glob
import html
import os
import struct
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))

# The viewer's data are capped: images longer than this are box-filtered down
# by an integer factor, and further while a scene's images together exceed
# MAX_SCENE_BYTES of half floats (the HTML holds them as base64, 4/3 larger).
MAX_SIDE = 512
MAX_SCENE_BYTES = 16 << 20


def _import_lightbench():
    try:
        import lightbench
        return lightbench
    except ImportError:
        pass
    # Run by hand from a checkout: the build's module, if it has been built.
    build = os.path.join(REPO, "build", "python")
    if os.path.isdir(build) and build not in sys.path:
        sys.path.append(build)
        try:
            import lightbench
            return lightbench
        except ImportError:
            pass
    return None


lightbench = _import_lightbench()


def data_uri(path):
    with open(path, "rb") as f:
        return "data:image/png;base64," + base64.b64encode(f.read()).decode()


def png_size(path):
    """(width, height) from a PNG's IHDR chunk, without decoding it."""
    with open(path, "rb") as f:
        head = f.read(24)
    if len(head) < 24 or head[:8] != b"\x89PNG\r\n\x1a\n":
        return None
    return struct.unpack(">II", head[16:24])


def srgb_to_linear(v):
    return np.where(v <= 0.04045, v / 12.92, ((v + 0.055) / 1.055) ** 2.4).astype(np.float32)


def read_png_linear(path):
    import matplotlib.image as mpimg
    a = mpimg.imread(path)
    if a.dtype != np.float32 and a.dtype != np.float64:
        a = a.astype(np.float32) / 255
    if a.ndim == 2:
        a = np.stack([a] * 3, axis=-1)
    return srgb_to_linear(np.asarray(a[..., :3], dtype=np.float32))


def read_exr(path):
    a = np.asarray(lightbench.read_exr(path), dtype=np.float32)
    if a.ndim != 3 or a.shape[2] < 3:
        raise ValueError(f"{path}: expected an (H, W, 3) image, got {a.shape}")
    return a[..., :3]


def reference_exr(run_dir, scene_meta, meta):
    """The path of the scene's reference EXR, or None; and where it looked.
    meta.json names it by "reference_exr" (relative to the run folder) when
    the runner copies it there; else by its cache key ("reference"), the cache
    being RESULTS/references/NAME-KEY.exr with RESULTS the run folder's
    grandparent (results/EXPERIMENT/RUN-ID); a given file by
    "reference_used": "file PATH"."""
    candidates = []
    for k in ("reference_exr", "reference_path", "reference_file"):  # a path relative to the run folder
        if scene_meta.get(k):
            candidates.append(os.path.join(run_dir, scene_meta[k]))
    used = scene_meta.get("reference_used") or ""
    if used.startswith("file "):
        given = used[5:]
        bases = [os.getcwd(), REPO, os.path.dirname(os.path.join(REPO, meta.get("experiment_file", "")))]
        candidates += [given] if os.path.isabs(given) else [os.path.join(b, given) for b in bases]
    key = scene_meta.get("reference") or ""
    roots = [os.path.dirname(os.path.dirname(os.path.abspath(run_dir))), os.path.join(REPO, "results")]
    if key:
        for root in dict.fromkeys(roots):
            candidates += sorted(glob.glob(os.path.join(glob.escape(root), "references", f"*-{glob.escape(key)}.exr")))
    for c in candidates:
        if os.path.isfile(c):
            return c, None
    where = (f"cache key {key} in " + " or ".join(os.path.join(r, "references") for r in dict.fromkeys(roots))
             if key else "meta.json names no reference file or cache key")
    return None, where


def downsample(a, f):
    if f == 1:
        return a
    h, w = a.shape[0] // f * f, a.shape[1] // f * f
    return a[:h, :w].reshape(h // f, f, w // f, f, 3).mean(axis=(1, 3), dtype=np.float64).astype(np.float32)


def encode_half(a):
    """Little-endian IEEE half floats, base64: 6 bytes a pixel. Finite values
    beyond half's range are clamped; NaN and Inf pass through (the viewer
    shows them magenta)."""
    finite = np.isfinite(a)
    a = np.where(finite, np.clip(a, -65504, 65504), a)
    return base64.b64encode(a.astype("<f2").tobytes()).decode("ascii")


def viewer_payload(run_dir, scene, labels, slugs, scene_meta, meta):
    """The viewer's data for one scene, or None when the run has no images.
    Returns (payload dict, list of notes for the report)."""
    entries = [("reference", f"{scene}__reference")] + [(l, f"{scene}__{slugs[l]}") for l in labels]
    entries = [(name, os.path.join(run_dir, stem)) for name, stem in entries]
    entries = [(n, s) for n, s in entries if os.path.exists(s + ".png") or os.path.exists(s + ".exr")]
    if not any(n == "reference" for n, _ in entries) or len(entries) < 2:
        return None, []
    notes = []
    images, source = None, "png"
    if lightbench is None:
        notes.append("the <code>lightbench</code> Python module is not importable, so the viewer shows the 8-bit "
                     "PNGs decoded to linear: its exposure is limited to the display range (values above 1 are "
                     "clipped)")
    else:
        ref_path, where = reference_exr(run_dir, scene_meta, meta)
        if ref_path is None:
            notes.append(f"the reference's EXR was not found ({html.escape(where)}), so the viewer shows every "
                         "image of this scene from its 8-bit PNG: its exposure is limited to the display range "
                         "(values above 1 are clipped)")
        else:
            try:
                images = [(n, read_exr(ref_path if n == "reference" else s + ".exr")) for n, s in entries]
                source = "exr"
            except Exception as e:  # a missing or unreadable EXR: the whole scene falls back together
                notes.append(f"an EXR could not be read ({html.escape(str(e))}), so the viewer shows the 8-bit "
                             "PNGs: its exposure is limited to the display range")
    if images is None:
        images = [(n, read_png_linear(s + ".png")) for n, s in entries if os.path.exists(s + ".png")]
    h, w = images[0][1].shape[:2]
    images = [(n, a) for n, a in images if a.shape[:2] == (h, w)]
    f = 1
    while max(w, h) / f > MAX_SIDE or len(images) * (w // f) * (h // f) * 6 > MAX_SCENE_BYTES:
        f += 1
    if f > 1:
        notes.append(f"the viewer's images are box-filtered down by {f}× ({w}×{h} to {w // f}×{h // f} pixels) to "
                     "keep this file small; the grid's images are full resolution")
    crop = scene_meta.get("crop")
    payload = {
        "scene": scene, "width": w // f, "height": h // f, "downsample": f, "source": source,
        "epsilon": meta.get("relmse_epsilon", 0.01),
        "crop": [c / f for c in crop] if crop else None,
        "images": [{"name": n, "data": encode_half(downsample(a, f))} for n, a in images],
    }
    return payload, notes
