"""The report's flip viewer: the data it embeds from EXRs, and (headless
Chromium) that the page's JavaScript runs without errors and the viewer
responds to keys, exposure and the error view. The synthetic run and its
fixtures are test_report.py's.

    /usr/bin/python3 -m pytest tests/python
"""
import base64
import json
import os
import re
import shutil
import subprocess

import numpy as np
import pytest

from test_report import CHROMIUM, images, mpimg, report  # noqa: F401 (report: a fixture)


def test_viewer_payload_from_exrs_keeps_values_above_one(tmp_path, monkeypatch):
    """With read_exr (faked here) the viewer gets linear values beyond the
    PNG's range; a long image is box-filtered to at most 512 pixels."""
    run_dir = tmp_path / "results" / "exp" / "run"
    run_dir.mkdir(parents=True)
    (tmp_path / "results" / "references").mkdir()
    big = np.full((300, 1100, 3), 0.5, np.float32)
    big[:, :3] = 17.0  # a light: the first 3x3 boxes of the filtered image stay at 17
    for stem in ("box__reference", "box__a"):
        mpimg.imsave(str(run_dir / (stem + ".png")), np.clip(big, 0, 1))
        (run_dir / (stem + ".exr")).write_bytes(b"")
    (tmp_path / "results" / "references" / "box-k1.exr").write_bytes(b"")

    class Fake:
        @staticmethod
        def read_exr(path):
            return big
    monkeypatch.setattr(images, "lightbench", Fake)
    payload, notes = images.viewer_payload(str(run_dir), "box", ["a"], {"a": "a"}, {"reference": "k1", "crop": None},
                                           {"relmse_epsilon": 0.01})
    assert payload["source"] == "exr" and payload["downsample"] == 3
    assert (payload["width"], payload["height"]) == (366, 100)
    assert any("box-filtered down by 3×" in n for n in notes)
    ref = np.frombuffer(base64.b64decode(payload["images"][0]["data"]), dtype="<f2").reshape(100, 366, 3)
    assert ref[0, 0, 0] == 17.0 and ref[0, 1, 0] == np.float16(0.5)


# ---- headless Chromium -------------------------------------------------------

# Appended to a copy of the report: drives the first viewer through keys and
# its exposure slider, and logs the centre pixel after each step.
HARNESS = """<script>
window.addEventListener('load', () => {
  const v = document.querySelector('.lb-viewer'), c = v.querySelector('canvas');
  // Read through a canvas of our own, made for readback (else Chromium logs a hint).
  const probe = document.createElement('canvas'), g = probe.getContext('2d', {willReadFrequently: true});
  probe.width = probe.height = 1;
  const px = () => {
    // Image pixel (18, 8) of 24 x 16: clear of the crop's red outline.
    g.drawImage(c, Math.floor(c.width * 0.77), Math.floor(c.height * 0.53), 1, 1, 0, 0, 1, 1);
    return Array.from(g.getImageData(0, 0, 1, 1).data.slice(0, 3));
  };
  const key = k => document.dispatchEvent(new KeyboardEvent('keydown', {key: k}));
  const out = {buttons: v.querySelectorAll('.lbv-button').length, method: px()};
  key('1'); out.unhovered = px();  // keys reach a viewer only under the pointer (or focused)
  v.dispatchEvent(new PointerEvent('pointerenter'));
  key('1'); out.reference = px(); out.name = v.querySelector('.lbv-name').textContent;
  const s = v.querySelector('input[type=range]'); s.value = 3; s.dispatchEvent(new Event('input'));
  out.brighter = px();
  key('3'); key('e'); out.error = px();
  console.log('harness ' + JSON.stringify(out));
});
</script>"""


def chromium(html_path, tmp_path, *extra):
    if not os.path.exists(CHROMIUM):
        pytest.skip("no /usr/bin/chromium")
    shot = str(tmp_path / "shot.png")
    cmd = [CHROMIUM, "--headless=new", "--no-sandbox", "--disable-gpu", "--no-first-run", "--enable-logging=stderr",
           "--v=0", f"--user-data-dir={tmp_path / 'profile'}", f"--screenshot={shot}", "--window-size=1280,1600",
           *extra, "file://" + html_path.replace(" ", "%20")]
    p = subprocess.run(cmd, capture_output=True, text=True, timeout=30)
    console = [l for l in p.stderr.splitlines() if "CONSOLE" in l or "Uncaught" in l]
    return shot, console


def unexpected(console):
    # Every console line must be one of ours: an exception or a console.error would be another.
    return [l for l in console if not re.search(r'"(viewer ready \d+ images|harness \{.*\})"', l)]


def test_chromium_runs_the_viewer(report, tmp_path):
    path, text = report
    harnessed = os.path.join(os.path.dirname(path), "harnessed report.html")
    with open(harnessed, "w", encoding="utf-8") as f:
        f.write(text.replace("</body>", HARNESS + "</body>"))
    shot, console = chromium(harnessed, tmp_path)
    assert not unexpected(console), console
    assert any('"viewer ready 3 images"' in l for l in console), console
    out = json.loads(next(re.search(r'"harness (\{.*\})"', l).group(1).replace('\\"', '"')
                          for l in console if '"harness {' in l))
    assert out["buttons"] == 3 and out["name"] == "reference"
    assert out["method"] != out["reference"], "key 1 flips to the reference"
    assert out["unhovered"] == out["method"], "keys elsewhere on the page leave the viewer alone"
    assert all(b >= r for b, r in zip(out["brighter"], out["reference"])) and out["brighter"] != out["reference"]
    # The error view's colour lies on the runner's false-colour ramp (five viridis stops, linear between).
    stops = np.array([[68, 1, 84], [59, 82, 139], [33, 145, 140], [94, 201, 98], [253, 231, 37]], float)
    ramp = np.array([np.interp(np.linspace(0, 4, 401), range(5), stops[:, c]) for c in range(3)]).T
    assert np.abs(ramp - out["error"]).sum(axis=1).min() < 6, out["error"]
    assert np.abs(ramp - out["brighter"]).sum(axis=1).min() > 6, "the image view is not on the ramp"
    image = mpimg.imread(shot)
    assert image.shape[1] == 1280 and image[..., :3].var() > 1e-3, "the screenshot is not blank"


def test_chromium_check_catches_a_broken_script(report, tmp_path):
    """The console check above must be able to fail: a syntax error in the
    inlined viewer shows as an uncaught error, and no "viewer ready"."""
    path, text = report
    broken = os.path.join(os.path.dirname(path), "broken report.html")
    with open(broken, "w", encoding="utf-8") as f:
        f.write(text.replace("'use strict';", "'use strict'; const = ;", 1))
    _, console = chromium(broken, tmp_path)
    assert unexpected(console) and not any("viewer ready" in l for l in console), console
    shutil.rmtree(tmp_path / "profile", ignore_errors=True)
