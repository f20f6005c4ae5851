"""The composer's page in a real browser: headless Chromium (Debian's ``chromium`` and ``chromium-driver``) driven
through WebDriver, against ``python -m jaxmotion.composer`` started on a free port. A person's session: draw a path,
split it in two, add an in-place action, set tags and durations, generate, watch the body play, scrub, download the
BVH and read it, save the program and load it back, and see a bad program refused with its message. The server is
given a body model (boxes on SMPL-24's bones, :mod:`toy_body`), so the page draws the skinned mesh; unticking "Mesh"
draws the skeleton.

``JAXMOTION_COMPOSER_RUN``: a trained run to serve instead of the test's tiny untrained one (the screenshots in
``docs/composer.md`` come from the cpu MARIONET), with ``JAXMOTION_COMPOSER_REVISER`` the profile of its revision
classifier (default smoke) and ``JAXMOTION_COMPOSER_CACHE`` the cache that holds it (default the test session's);
``JAXMOTION_COMPOSER_SHOTS``: a folder for the screenshots.
"""

import json
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import jax
import pytest

from jaxmotion.data import synthetic
from jaxmotion.data.export import load_bvh
from jaxmotion.models.marionet import MarionetConfig, init_marionet
from jaxmotion.pipelines.artefacts import DataFacts
from jaxmotion.pipelines.marionette import ContextGenerator, start_bank
from toy_body import box_body

webdriver = pytest.importorskip("selenium.webdriver")
from selenium.webdriver.chrome.service import Service  # noqa: E402
from selenium.webdriver.common.action_chains import ActionChains  # noqa: E402
from selenium.webdriver.common.by import By  # noqa: E402
from selenium.webdriver.common.keys import Keys  # noqa: E402
from selenium.webdriver.support.ui import Select, WebDriverWait  # noqa: E402

CHROMIUM, DRIVER = shutil.which("chromium"), shutil.which("chromedriver")
pytestmark = [pytest.mark.browser, pytest.mark.integration,
              pytest.mark.skipif(not (CHROMIUM and DRIVER), reason="Debian's chromium and chromium-driver are not "
                                 "installed (.ci/run installs them)")]
SHOTS = os.environ.get("JAXMOTION_COMPOSER_SHOTS")


@pytest.fixture(scope="module")
def url(tmp_path_factory):
    run = os.environ.get("JAXMOTION_COMPOSER_RUN")
    if run is None:
        takes = synthetic.generate("synth-mag", "test", seed=0, count=4, progress=False)
        config = MarionetConfig.tiny(max_frames=40)
        params = jax.jit(init_marionet, static_argnums=1)(jax.random.key(0), config)
        run = ContextGenerator(config, params, DataFacts.of(takes), start_bank(takes, per_tag=2),
                               max_frames=40).save(tmp_path_factory.mktemp("run") / "generator")
    body = box_body(tmp_path_factory.mktemp("body") / "boxes.npz")
    server = subprocess.Popen([sys.executable, "-m", "jaxmotion.composer", str(run), "--port", "0",
                               "--reviser-profile", os.environ.get("JAXMOTION_COMPOSER_REVISER", "smoke"),
                               "--body-model", str(body)],
                              stderr=subprocess.PIPE, text=True, env={**os.environ, "JAXMOTION_CACHE": os.environ.get(
                                  "JAXMOTION_COMPOSER_CACHE", os.environ["JAXMOTION_CACHE"])})
    try:
        lines = []
        for line in server.stderr:  # the command says where it serves once it has compiled
            lines.append(line)
            found = re.search(r"serving the composer at (http://\S+/)", line)
            if found:
                break
        else:
            pytest.fail(f"the composer did not start: {''.join(lines)[-2000:]}")
        yield found[1]
    finally:
        server.terminate()
        server.wait(timeout=30)


@pytest.fixture(scope="module")
def browser(tmp_path_factory):
    downloads = tmp_path_factory.mktemp("downloads")
    options = webdriver.ChromeOptions()
    options.binary_location = CHROMIUM
    for argument in ("--headless=new", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage",
                     "--window-size=1400,1250"):
        options.add_argument(argument)
    options.add_experimental_option("prefs", {"download.default_directory": str(downloads),
                                              "download.prompt_for_download": False})
    driver = webdriver.Chrome(service=Service(DRIVER), options=options)
    driver.execute_cdp_cmd("Page.setDownloadBehavior", {"behavior": "allow", "downloadPath": str(downloads)})
    driver.downloads = downloads
    yield driver
    driver.quit()


def _wait(driver, condition, timeout=120):
    return WebDriverWait(driver, timeout).until(lambda d: condition())


def _downloaded(driver, name):
    path = Path(driver.downloads) / name
    _wait(driver, lambda: path.is_file() and not Path(f"{path}.crdownload").exists(), 30)
    return path


def _shot(driver, name):
    if SHOTS:
        Path(SHOTS).mkdir(parents=True, exist_ok=True)
        driver.save_screenshot(str(Path(SHOTS) / name))


def _pixels(driver):  # the 3D view's pixels, as numbers
    return driver.execute_script("const c = document.getElementById('view');"
                                 "return Array.from(c.getContext('2d').getImageData(0, 0, c.width, c.height).data);")


def _differing(a, b):  # pixels of which some channel moved by more than 40
    return sum(any(abs(x - y) > 40 for x, y in zip(a[i:i + 4], b[i:i + 4])) for i in range(0, len(a), 4))


def test_a_person_composes_watches_downloads_and_is_told_what_is_wrong(url, browser):
    d = browser
    d.get(url)
    _wait(d, lambda: d.find_element(By.TAG_NAME, "body").get_attribute("data-ready") == "true", 30)
    empty = _pixels(d)
    ground = d.find_element(By.ID, "ground")
    metre = d.execute_script("const c = arguments[0]; return c.getBoundingClientRect().width / 10;", ground)

    def click(x, z):  # a ground point (metres; the view spans -5..5 until paths reach further)
        ActionChains(d).move_to_element_with_offset(ground, x * metre, -z * metre).click().perform()

    d.find_element(By.ID, "draw").click()
    for point in ((0.2, 1.0), (0.4, 2.2), (1.4, 3.2), (2.8, 3.4)):
        click(*point)
    d.find_element(By.ID, "finish").click()
    d.find_element(By.ID, "split").click()
    click(0.4, 2.2)  # the path becomes two actions
    d.find_element(By.ID, "in-place").click()
    rows = d.find_elements(By.CSS_SELECTOR, "#actions tbody tr")
    assert [r.find_elements(By.TAG_NAME, "td")[1].text.split()[0] for r in rows] == ["path", "path", "in"]
    for row, tag, seconds in zip(rows, ("Walk", "Run", "Kick"), ("0.8", "0.5", "0.6")):
        Select(row.find_element(By.CSS_SELECTOR, "select.tag")).select_by_value(tag)
        box = row.find_element(By.CSS_SELECTOR, "input.seconds")
        box.clear()
        box.send_keys(seconds, Keys.TAB)
    _shot(d, "composer-drawing.png")

    d.find_element(By.ID, "generate").click()
    _wait(d, lambda: d.find_element(By.ID, "player").get_attribute("data-state") == "playing")
    status = d.find_element(By.ID, "status").text
    assert re.match(r"\d+ frames, 3 actions; ", status), status
    frames = int(status.split()[0])
    assert _differing(_pixels(d), empty) > 500  # the body, its path and the grid where the motion is

    scrub = d.find_element(By.ID, "scrub")
    scrub.send_keys(Keys.HOME)  # scrubbing pauses
    _wait(d, lambda: d.find_element(By.ID, "player").get_attribute("data-state") == "paused", 10)
    first = _pixels(d)
    scrub.send_keys(Keys.END)
    assert d.find_element(By.ID, "frame").text == f"frame {frames} / {frames}"
    assert _differing(_pixels(d), first) > 100  # the body moved; the scene around it did not
    d.execute_script("const s = document.getElementById('scrub'); s.value = Math.floor(s.max * 0.55);"
                     "s.dispatchEvent(new Event('input'));")
    _shot(d, "composer-mesh.png")
    mesh = _pixels(d)
    d.find_element(By.ID, "mesh").click()  # the skeleton instead
    assert _differing(_pixels(d), mesh) > 100
    _shot(d, "composer-playing.png")

    d.find_element(By.LINK_TEXT, "Download motion.bvh").click()
    assert load_bvh(_downloaded(d, "motion.bvh")).rotations.shape[0] == frames
    d.find_element(By.ID, "save").click()
    saved = json.loads(_downloaded(d, "program.json").read_text())
    assert [a["tags"][0] for a in saved["actions"]] == ["Walk", "Run", "Kick"]
    d.find_element(By.ID, "clear").click()
    assert not d.find_elements(By.CSS_SELECTOR, "#actions tbody tr")
    d.find_element(By.ID, "load").send_keys(str(_downloaded(d, "program.json")))
    _wait(d, lambda: len(d.find_elements(By.CSS_SELECTOR, "#actions tbody tr")) == 3, 10)

    box = d.find_elements(By.CSS_SELECTOR, "#actions input.seconds")[0]
    box.clear()
    box.send_keys("100", Keys.TAB)  # longer than the model's longest action
    d.find_element(By.ID, "generate").click()
    message = _wait(d, lambda: "error" in d.find_element(By.ID, "status").get_attribute("class")
                    and d.find_element(By.ID, "status").text, 60)
    assert message.startswith("actions[0].seconds: expected 1 to"), message
    assert d.find_element(By.ID, "player").get_attribute("data-state") == "paused"  # the last motion stays
