"""A rendered MP4 plays in a browser: headless Chromium (Debian's ``chromium`` and ``chromium-driver``, as the
composer's browser tests use) loads it in a ``<video>`` element, reports its size and duration, and draws its first
and last frames, which differ (the walk moves). Skipped where Chromium or selenium is missing."""

import shutil
import time

import numpy as np
import pytest

from jaxmotion.data import synthetic
from jaxmotion.viz.video import render_video

webdriver = pytest.importorskip("selenium.webdriver")
from selenium.webdriver.chrome.service import Service  # noqa: E402

CHROMIUM, DRIVER = shutil.which("chromium"), shutil.which("chromedriver")
pytestmark = [pytest.mark.browser, pytest.mark.integration,
              pytest.mark.skipif(not (CHROMIUM and DRIVER), reason="Debian's chromium and chromium-driver are not "
                                                                  "installed (.ci/run installs them)"),
              pytest.mark.filterwarnings(r"ignore:os\.fork\(\) was called:RuntimeWarning")]  # chromedriver's start

FRAMES, FPS = 30, 20.0
PAGE = """<!doctype html><video id="v" src="walk.mp4" muted preload="auto"></video><canvas id="c"></canvas>
<script>
const v = document.getElementById("v"), c = document.getElementById("c");
function frame() {  // the sum of the frame's RGB values, drawn to a canvas
  c.width = v.videoWidth; c.height = v.videoHeight; const g = c.getContext("2d"); g.drawImage(v, 0, 0);
  const d = g.getImageData(0, 0, c.width, c.height).data; let s = 0;
  for (let i = 0; i < d.length; i += 4) s += d[i] + d[i + 1] + d[i + 2];
  return s;
}
v.addEventListener("error", () => { window.played = {error: v.error ? v.error.code : -1}; });
v.addEventListener("loadeddata", () => {
  const first = frame();
  v.addEventListener("seeked", () => {
    window.played = {width: v.videoWidth, height: v.videoHeight, duration: v.duration, first: first, last: frame()};
  }, {once: true});
  v.currentTime = v.duration - 0.5 / 20;
});
</script>"""


def test_a_rendered_mp4_plays_in_chromium(tmp_path):
    walks = synthetic.generate("synth-cmu", "train", seed=0, count=8, progress=False)
    render_video(tmp_path / "walk.mp4", walks, indices=[5], fps=FPS, max_frames=FRAMES)
    (tmp_path / "page.html").write_text(PAGE)
    options = webdriver.ChromeOptions()
    options.binary_location = CHROMIUM
    for argument in ("--headless=new", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage",
                     "--allow-file-access-from-files"):  # else the file:// video taints the canvas
        options.add_argument(argument)
    driver = webdriver.Chrome(service=Service(DRIVER), options=options)
    try:
        driver.get((tmp_path / "page.html").as_uri())
        deadline, played = time.monotonic() + 60, None
        while played is None and time.monotonic() < deadline:
            played = driver.execute_script("return window.played || null")
            time.sleep(0.1)
    finally:
        driver.quit()
    assert played is not None and "error" not in played, played
    assert played["width"] > 100 and played["height"] > 100
    assert played["duration"] == pytest.approx(FRAMES / FPS, abs=1.5 / FPS)
    assert not np.isclose(played["first"], played["last"], rtol=1e-4)  # another frame: the body has moved
