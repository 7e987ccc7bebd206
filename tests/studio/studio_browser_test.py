#!/usr/bin/python3
"""End-to-end test of `rosyhatch studio` in a real browser: headless Chromium driven
by chromium-driver and python3-selenium (Debian packages, installed by
tools/setup.sh). Opens the page, waits for the mesh, clicks the bunny to add a
singular element and sees the singularity count change, cancels a pair by clicking
two singularities, saves, and renders the saved scene with `rosyhatch render`.

  studio_browser_test.py ROSYHATCH DATA_DIR [--screenshot OUT.png] [--mesh MESH] [--display-above N]

With --display-above N (below the mesh's faces) the page gets a display mesh (the
path a 270k-face mesh takes, docs/studio.md): the test also checks that it was
decimated and that the clicked element lies on the full mesh's surface, drags it,
and stops there (the rest does not depend on the mesh shown).

Exit 77 (ctest: skipped) with a message when Chromium, its driver or selenium is missing.
"""
import json
import math
import os
import shutil
import subprocess
import sys
import tempfile
import time

SKIP = 77


def skip(why):
    print(f"SKIPPED: {why} (tools/setup.sh installs chromium chromium-driver python3-selenium)")
    sys.exit(SKIP)


def distance_to_mesh(off_path, p):
    """Distance from p to the nearest face of an OFF mesh whose plane it projects
    into (point in triangle), over faces with a corner near p, relative to the
    bounding box's diagonal; inf if none."""
    with open(off_path) as f:
        words = [w for line in f if not line.startswith("#") for w in line.split()]
    assert words[0] == "OFF", off_path
    nv, nf = int(words[1]), int(words[2])
    xyz = [tuple(float(w) for w in words[4 + 3 * i:7 + 3 * i]) for i in range(nv)]
    at = 4 + 3 * nv
    diag2 = sum((max(q[k] for q in xyz) - min(q[k] for q in xyz)) ** 2 for k in range(3))
    sub = lambda a, b: (a[0] - b[0], a[1] - b[1], a[2] - b[2])
    dot = lambda a, b: a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
    cross = lambda a, b: (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])
    best = float("inf")
    for _ in range(nf):
        k = int(words[at])
        a, b, c = (xyz[int(w)] for w in words[at + 1:at + 4])
        at += 1 + k
        if min(dot(sub(q, p), sub(q, p)) for q in (a, b, c)) > 1e-4 * diag2:
            continue
        n = cross(sub(b, a), sub(c, a))
        nn = dot(n, n) ** 0.5
        if nn == 0:
            continue
        inside = all(dot(cross(sub(v, u), sub(p, u)), n) >= -1e-12 * nn for u, v in ((a, b), (b, c), (c, a)))
        if inside:
            best = min(best, abs(dot(n, sub(p, a))) / nn)
    return best / diag2 ** 0.5


def main():
    args = sys.argv[1:]
    screenshot = None
    if "--screenshot" in args:
        i = args.index("--screenshot")
        screenshot = args[i + 1]
        del args[i:i + 2]
    mesh = None
    if "--mesh" in args:  # another mesh than bunny00 (timings on big meshes, docs/studio.md)
        i = args.index("--mesh")
        mesh = args[i + 1]
        del args[i:i + 2]
    display_above = None
    if "--display-above" in args:
        i = args.index("--display-above")
        display_above = args[i + 1]
        del args[i:i + 2]
    rosyhatch, data = args
    mesh = mesh or f"{data}/meshes/bunny00.off"
    chromium = shutil.which("chromium")
    driver_path = shutil.which("chromedriver") or "/usr/bin/chromedriver"
    if not chromium:
        skip("chromium is not installed")
    if not os.path.exists(driver_path):
        skip("chromedriver (chromium-driver) is not installed")
    try:
        from selenium import webdriver
        from selenium.webdriver.chrome.service import Service
        from selenium.webdriver.common.action_chains import ActionChains
        from selenium.webdriver.common.by import By
        from selenium.webdriver.support.ui import WebDriverWait
    except ImportError:
        skip("python3-selenium is not installed")

    work = tempfile.mkdtemp(prefix="rosy-studio-browser-")
    scene = os.path.join(work, "bunny.yaml")
    with open(scene, "w") as f:
        f.write(f"""# the default scene's view of the bunny
mesh: {mesh}
camera:
  auto: true
  direction: [-0.35, 0.3, 1.0]
  fov: 30
  margin: 0.08
  resolution: [256, 256]
lights:
  - {{type: directional, direction: [-1.0, 0.8, 0.35], intensity: 0.85}}
style:
  ambient: 0.08
output: bunny.png
""")
    extra = ["--display-above", display_above] if display_above else []
    server = subprocess.Popen([rosyhatch, "studio", scene] + extra, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    driver = None
    try:
        server.stdout.readline()  # "rosyhatch studio: SCENE"
        url = server.stdout.readline().strip()
        assert url.startswith("http://127.0.0.1:") and "token=" in url, url

        options = webdriver.ChromeOptions()
        for a in ("--headless=new", "--no-sandbox", "--use-gl=swiftshader", "--enable-unsafe-swiftshader",
                  "--window-size=1280,800", "--disable-dev-shm-usage"):
            options.add_argument(a)
        options.binary_location = chromium
        driver = webdriver.Chrome(service=Service(executable_path=driver_path), options=options)
        driver.get(url)
        wait = WebDriverWait(driver, 60)
        wait.until(lambda d: d.find_element(By.TAG_NAME, "body").get_attribute("data-loaded"))
        count = lambda: int(driver.find_element(By.ID, "sing-count").text)
        n0 = count()
        print(f"page loaded in {driver.find_element(By.TAG_NAME, 'body').get_attribute('data-loaded')} ms, {n0} singularities")
        assert n0 > 0

        # A +1 element where the canvas's centre hits the bunny.
        canvas = driver.find_element(By.ID, "canvas")
        driver.find_element(By.ID, "mode-plus").click()
        hits = driver.execute_script("""
            const c = document.getElementById('canvas'); return [c.clientWidth, c.clientHeight];""")
        ActionChains(driver).move_to_element(canvas).click().perform()
        wait.until(lambda d: len(d.execute_script("return window.studio.state().elements")) == 1)
        n1 = count()
        print(f"element added at the canvas centre ({hits[0] // 2}, {hits[1] // 2}): {n0} -> {n1} singularities; "
              f"page: {driver.find_element(By.ID, 'status').text}")
        assert n1 != n0, "adding a +1 element did not change the singularity count"
        display = driver.execute_script("return window.studio.state().display")
        assert display["decimated"] or not display_above, display
        if display["decimated"]:
            p = driver.execute_script("return window.studio.state().elements")[0]["position"]
            d = distance_to_mesh(mesh, p)
            print(f"display mesh: {display['faces']} faces; the element is {d:.2e} diagonals from the full mesh")
            assert d < 1e-8, f"the click did not land on the full mesh's surface ({d})"

        # Drag the element 40 px to the right: it moves there (on the surface).
        driver.find_element(By.ID, "mode-move").click()
        el = driver.execute_script("return window.studio.elementsOnScreen()")[0]
        old = el["position"]
        w, h = hits
        (ActionChains(driver).move_to_element_with_offset(canvas, int(el["x"] - w / 2), int(el["y"] - h / 2))
         .click_and_hold().move_by_offset(20, 0).move_by_offset(20, 0).release().perform())
        wait.until(lambda d: d.execute_script("return window.studio.state().elements")[0]["position"] != old)
        moved = driver.execute_script("return window.studio.elementsOnScreen()")[0]
        print(f"element dragged from ({el['x']:.0f}, {el['y']:.0f}) to ({moved['x']:.0f}, {moved['y']:.0f})")
        assert abs(moved["x"] - el["x"] - 40) < 3 and abs(moved["y"] - el["y"]) < 3, (el, moved)

        if display_above:  # the rest does not depend on the display mesh: covered by the full run
            return 0

        # The element's phase from the list, then a direction element (a click at the
        # centre, free again) turned by 15 degrees with its list button.
        phase = driver.find_element(By.CSS_SELECTOR, "#elements .element-phase")
        driver.execute_script("arguments[0].value = '45'; arguments[0].dispatchEvent(new Event('change'))", phase)
        wait.until(lambda d: d.execute_script("return window.studio.state().elements")[0]["phase"] == 45)
        driver.find_element(By.ID, "mode-regular").click()
        ActionChains(driver).move_to_element(canvas).click().perform()
        wait.until(lambda d: len(d.execute_script("return window.studio.state().elements")) == 2)
        d0 = driver.execute_script("return window.studio.state().elements")[1]["direction"]
        driver.find_element(By.CSS_SELECTOR, "#elements li:nth-child(2) .turn-ccw").click()
        wait.until(lambda d: d.execute_script("return window.studio.state().elements")[1]["direction"] != d0)
        e1 = driver.execute_script("return window.studio.state().elements")[1]
        d1, n = e1["direction"], e1["normal"]
        # The turn in the tangent plane of the element's face (the state's normal),
        # counter-clockwise seen from outside.
        dot = lambda a, b: sum(x * y for x, y in zip(a, b))
        flat = lambda v: [x - dot(v, n) * y for x, y in zip(v, n)]
        p0, p1 = flat(d0), flat(d1)
        cross = [p0[1] * p1[2] - p0[2] * p1[1], p0[2] * p1[0] - p0[0] * p1[2], p0[0] * p1[1] - p0[1] * p1[0]]
        turn = math.degrees(math.atan2(dot(cross, n), dot(p0, p1)))
        print(f"phase set to 45 from the list; direction element turned by {turn:.2f} degrees")
        assert abs(turn - 15) < 0.5, (d0, d1, n)
        # Its marker is a handle: a drag from it to the right re-aims it to the right.
        el = driver.execute_script("return window.studio.elementsOnScreen()")[1]
        (ActionChains(driver).move_to_element_with_offset(canvas, int(el["x"] - w / 2), int(el["y"] - h / 2))
         .click_and_hold().move_by_offset(20, 0).move_by_offset(20, 0).release().perform())
        wait.until(lambda d: d.execute_script("return window.studio.state().elements")[1]["direction"] != d1)
        d2 = driver.execute_script("return window.studio.state().elements")[1]["direction"]
        tip = driver.execute_script(
            "const st = window.studio.state(), e = st.elements[1];"
            "const diag = Math.hypot(...st.bounds.max.map((x, k) => x - st.bounds.min[k]));"
            "const s = 0.03 * diag / Math.hypot(...e.direction);"
            "return window.studio.screenOf(e.position.map((x, k) => x + s * e.direction[k]))")
        dx, dy = tip["x"] - el["x"], tip["y"] - el["y"]
        print(f"direction element re-aimed by dragging its marker: on screen ({dx:.1f}, {dy:.1f})")
        assert dx > 0 and abs(dy) < 0.5 * dx, (d1, d2, dx, dy)

        # Cancel the closest visible opposite pair by clicking the two dots.
        driver.find_element(By.ID, "mode-cancel").click()
        sings = [s for s in driver.execute_script("return window.studio.singularitiesOnScreen()") if s["visible"]]
        pos = [s for s in sings if s["index_numerator"] == 1]
        neg = [s for s in sings if s["index_numerator"] == -1]
        pairs = sorted(((sum((a["position"][k] - b["position"][k]) ** 2 for k in range(3)), a, b)
                        for a in pos for b in neg
                        if (a["x"] - b["x"]) ** 2 + (a["y"] - b["y"]) ** 2 > 12 ** 2), key=lambda t: t[0])
        assert pairs, "no visible opposite pair to cancel"
        before = count()
        for _, a, b in pairs[:5]:
            for s in (a, b):
                ActionChains(driver).move_to_element_with_offset(canvas, int(s["x"] - w / 2), int(s["y"] - h / 2)).click().perform()
            try:
                WebDriverWait(driver, 20).until(lambda d: count() == before - 2)
                print(f"cancelled {a['id']} and {b['id']}: {before} -> {count()} singularities; "
                      f"page: {driver.find_element(By.ID, 'status').text}")
                break
            except Exception:
                print("status:", driver.find_element(By.ID, "status").text)
        assert count() == before - 2, "no pair was cancelled"

        # The original beside the edited preview.
        driver.find_element(By.ID, "preview-original").click()
        wait.until(lambda d: d.execute_script(
            "const i = document.getElementById('preview-original-img'); return i.complete && i.naturalWidth > 0"))
        assert driver.find_element(By.ID, "original-figure").is_displayed()
        print("original preview shown beside the edited one")

        # Save beside the scene.
        name = driver.find_element(By.ID, "save-name")
        name.clear()
        name.send_keys("saved.yaml")
        driver.find_element(By.ID, "save").click()
        wait.until(lambda d: d.find_element(By.ID, "save-result").get_attribute("data-path"))
        saved = driver.find_element(By.ID, "save-result").get_attribute("data-path")
        assert saved == os.path.join(work, "saved.yaml"), saved
        if screenshot:
            wait.until(lambda d: d.find_element(By.ID, "preview").get_attribute("src"))
            time.sleep(1.0)
            driver.set_window_size(1280, 1000)  # room for the preview in the panel
            time.sleep(1.0)
            driver.execute_script("document.getElementById('panel').scrollTop = 0")
            driver.save_screenshot(screenshot)
        text = open(saved).read()
        assert "cancel_near" in text and "order: 1" in text and "# the default scene's view" in text, text

        out = os.path.join(work, "saved.png")
        r = subprocess.run([rosyhatch, "render", saved, "-q", "-o", out], capture_output=True, text=True)
        assert r.returncode == 0, r.stderr
        assert os.path.getsize(out) > 1000
        print("saved scene rendered:", out)
        return 0
    finally:
        if driver:
            driver.quit()
        server.terminate()
        try:
            server.wait(10)
        except subprocess.TimeoutExpired:
            server.kill()
        shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    sys.exit(main())
