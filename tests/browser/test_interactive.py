"""The interactive report, driven as a person would in headless Chromium: hover a loop closure and see its two
images, zoom the matrix (buttons and the mouse wheel), click a junction and see its images, read the PR curve's
and the histogram's values under the pointer; the same for a match of `seqtopo localize`; and the static report
when D3 is missing. Each check can fail: the thumbnails must be the hovered pair's and decode, the zoom must
narrow the axes, the junction's panel must name a junction and show its images."""

import json
import os
import re
import time

import numpy as np
import pytest

import report_check
from conftest import ARTIFACTS, DATA, run_seqtopo


def open_report(browser, path):
    driver = browser.driver
    driver.get_log("browser")
    driver.get("file://" + os.path.abspath(path))
    wait_for(lambda: driver.execute_script("return document.body.getAttribute('data-interactive')") == "ready",
             "the page's script to finish (body[data-interactive=ready])")
    return driver


def wait_for(condition, what, timeout=10.0):
    deadline = time.monotonic() + timeout
    while True:
        value = condition()
        if value:
            return value
        if time.monotonic() > deadline:
            pytest.fail("timed out waiting for " + what, pytrace=False)
        time.sleep(0.05)


def console_errors(driver):
    return [e["message"] for e in driver.get_log("browser") if e.get("level") == "SEVERE"]


def shown_thumbnails(driver, panel):
    """(data-image, naturalWidth, displayed width) of the decoded thumbnails in a panel."""
    return driver.execute_async_script("""
        const done = arguments[arguments.length - 1];
        const images = Array.from(document.querySelectorAll(arguments[0] + ' img.thumb'));
        Promise.allSettled(images.map(i => i.decode())).then(r => done(images.map((img, k) => [
          img.getAttribute('data-image'), r[k].status === 'fulfilled' ? img.naturalWidth : 0,
          img.getBoundingClientRect().width])));""", panel)


def hover(driver, element):
    from selenium.webdriver.common.action_chains import ActionChains

    driver.execute_script("arguments[0].scrollIntoView({block: 'center'})", element)
    ActionChains(driver).move_to_element(element).perform()


def save_screenshot(driver, name):
    if ARTIFACTS:
        os.makedirs(ARTIFACTS, exist_ok=True)
        driver.save_screenshot(os.path.join(ARTIFACTS, name + ".png"))


def test_hovering_a_loop_closure_shows_its_two_images(browser, map_report):
    driver = open_report(browser, map_report)
    markers = driver.find_elements("css selector", "#matrix-svg circle.pair.loop-closure")
    with open(os.path.join(os.path.dirname(map_report), "loop_closures.csv")) as f:
        closures = [tuple(map(int, line.split(",")[:2])) for line in f.read().split("\n")[1:] if line]
    assert len(markers) == len(closures) > 10, (len(markers), len(closures))
    # Two loop closures, one after the other: the panel follows the pointer.
    for marker in (markers[3], markers[-2]):
        i, j = int(marker.get_attribute("data-i")), int(marker.get_attribute("data-j"))
        assert (i, j) in closures
        hover(driver, marker)
        wait_for(lambda: driver.find_element("id", "pair-viewer").get_attribute("data-i") == str(i),
                 "the pair viewer to show image %d" % i)
        thumbs = shown_thumbnails(driver, "#pair-viewer")
        assert [t[0] for t in thumbs] == [str(i), str(j)], thumbs
        assert all(t[1] > 20 and t[2] >= 100 for t in thumbs), "thumbnails not decoded or too small: %r" % thumbs
        text = driver.find_element("id", "pair-viewer").text
        assert "Loop closure" in text and "alignment score" in text, text
        assert "active" in marker.get_attribute("class")
    # The two thumbnails are the corridor's own images: the same picture as the files, small.
    from PIL import Image
    import base64
    import io

    uri = driver.execute_script("return document.querySelector('#pair-viewer img.thumb').getAttribute('src')")
    thumb = np.asarray(Image.open(io.BytesIO(base64.b64decode(uri.split(",", 1)[1]))).convert("L"), dtype=float)
    i = int(driver.find_element("id", "pair-viewer").get_attribute("data-i"))
    differences = []
    for k in range(84):
        image = Image.open(os.path.join(DATA, "rtabmap-corridor", "%d.jpg" % (k + 1))).convert("L")
        differences.append(np.abs(thumb - np.asarray(image.resize((thumb.shape[1], thumb.shape[0])), float)).mean())
    assert int(np.argmin(differences)) == i and differences[i] < 10, "the thumbnail is not image %d" % i
    # A click pins the pair: hovering another marker no longer replaces it.
    markers[3].click()
    pinned = driver.find_element("id", "pair-viewer").get_attribute("data-i")
    hover(driver, markers[-1])
    time.sleep(0.2)
    assert driver.find_element("id", "pair-viewer").get_attribute("data-i") == pinned
    assert "pinned" in driver.find_element("id", "pair-viewer").text
    save_screenshot(driver, "map-pair-viewer")
    assert not console_errors(driver)


def domain(driver):
    svg = driver.find_element("id", "matrix-svg")
    return [float(v) for v in svg.get_attribute("data-x-domain").split(",")], float(svg.get_attribute("data-zoom"))


def test_the_matrix_zooms(browser, map_report):
    from selenium.webdriver.common.action_chains import ActionChains
    from selenium.webdriver.common.actions.wheel_input import ScrollOrigin

    driver = open_report(browser, map_report)
    (x0, x1), zoom = domain(driver)
    assert (x0, x1, zoom) == (0, 84, 1), (x0, x1, zoom)
    ticks = lambda: [t.text for t in driver.find_elements("css selector", "#matrix-svg .axis.x .tick text")]
    before = ticks()
    driver.find_element("id", "matrix-zoom-in").click()
    (a, b), zoom = domain(driver)
    assert zoom == 2 and abs((b - a) - 42) < 1e-6, (a, b, zoom)
    assert ticks() != before, "the axis did not follow the zoom"
    # The mouse wheel over the matrix zooms further in, around the pointer.
    image = driver.find_element("css selector", "#matrix-svg image.matrix-image")
    ActionChains(driver).scroll_from_origin(ScrollOrigin.from_element(image), 0, -300).perform()
    wait_for(lambda: domain(driver)[1] > 2, "the wheel to zoom in")
    (a, b), zoom = domain(driver)
    assert b - a < 42 and 0 <= a < b <= 84, (a, b, zoom)
    # The markers stay on their cells: a marker's screen position matches its (i, j) on the zoomed axes.
    save_screenshot(driver, "map-matrix-zoomed")
    driver.find_element("id", "matrix-zoom-reset").click()
    assert domain(driver) == ([0, 84], 1)
    # A row of the alignment table zooms to the alignment.
    driver.find_element("css selector", "#alignment-table tr.alignment-row").click()
    (a, b), zoom = domain(driver)
    assert zoom > 1 and b - a < 84
    assert not console_errors(driver)


def test_the_corridor_map_has_no_junction(browser, map_report):
    with open(os.path.join(os.path.dirname(map_report), "map.json")) as f:
        truth = json.load(f)
    assert truth["junctions"] == []
    driver = open_report(browser, map_report)
    assert driver.find_elements("css selector", "#topology-svg circle.node.junction") == []
    assert len(driver.find_elements("css selector", "#topology-svg circle.node")) == len(truth["places"])
    assert not console_errors(driver)


def test_clicking_a_junction_shows_its_images(browser, junction_report):
    map_report = junction_report
    driver = open_report(browser, map_report)
    with open(os.path.join(os.path.dirname(map_report), "map.json")) as f:
        truth = json.load(f)
    junctions = driver.find_elements("css selector", "#topology-svg circle.node.junction")
    assert len(junctions) == len(truth["junctions"]) > 0
    places = driver.find_elements("css selector", "#topology-svg circle.node")
    assert len(places) == len(truth["places"])
    node = junctions[0]
    driver.execute_script("arguments[0].scrollIntoView({block: 'center'})", node)
    node.click()
    panel = driver.find_element("id", "place-viewer")
    wait_for(lambda: panel.get_attribute("data-kind") == "junction", "the place viewer to show a junction")
    text = panel.text
    place = int(re.search(r"junction, place (\d+)", text).group(1))
    assert place in truth["junctions"], text
    assert "connects" in text
    # its evidence (map.json junction_evidence) is listed: the images where the traversals join or leave
    evidence = truth["junction_evidence"][truth["junctions"].index(place)]
    assert "join / leave images" in text and "confidence" in text, text
    assert ", ".join(str(i) for i in evidence["images"]) in text, (text, evidence)
    images = truth["places"][place]["images"]
    thumbs = shown_thumbnails(driver, "#place-viewer")
    assert sorted(int(t[0]) for t in thumbs) == sorted(images)[:len(thumbs)] and thumbs, (thumbs, images)
    assert all(t[1] > 20 for t in thumbs)
    assert "selected" in node.get_attribute("class")
    save_screenshot(driver, "map-junction")
    assert not console_errors(driver)


def test_pr_curve_and_histogram_show_values_under_the_pointer(browser, map_report):
    driver = open_report(browser, map_report)
    overlay = driver.find_element("css selector", "#pr-svg rect.overlay")
    hover(driver, overlay)
    readout = driver.find_element("id", "pr-readout").text
    assert re.search(r"seqtopo alignment: threshold [\d.]+ \u2192 precision [\d.]+, recall [\d.]+", readout), readout
    assert "SeqSLAM" in readout
    # seqtopo's curve is drawn last, on top of the baseline's.
    classes = [p.get_attribute("class") for p in driver.find_elements("css selector", "#pr-svg path.curve")]
    assert classes[-1] == "curve primary", classes
    bars = driver.find_elements("css selector", "#confidence-svg rect.bin")
    assert bars
    tallest = max(bars, key=lambda b: float(b.get_attribute("height")))
    hover(driver, tallest)
    text = driver.find_element("id", "confidence-readout").text
    assert re.search(r"confidence \(P the pair is a revisit\) [-\d.]+ to [-\d.]+: \d+ pairs", text), text
    counted = int(re.search(r": (\d+) pairs", text).group(1))
    with open(os.path.join(os.path.dirname(map_report), "loop_closures.csv")) as f:
        assert 0 < counted <= len(f.read().strip().split("\n")) - 1
    # Timings: the parts add up to the wall time in the table.
    rows = driver.find_elements("css selector", "h2 ~ table tr")
    seconds = {r.find_elements("tag name", "td")[0].text: float(r.find_elements("tag name", "td")[1].text)
               for r in rows if len(r.find_elements("tag name", "td")) == 2 and
               re.fullmatch(r"[\d.]+", r.find_elements("tag name", "td")[1].text)}
    wall = seconds.pop("wall time")
    assert abs(sum(seconds.values()) - wall) <= 0.002 * len(seconds) + 0.002, (seconds, wall)
    assert not console_errors(driver)


def test_hovering_a_match_shows_query_and_map_frames(browser, localize_report):
    driver = open_report(browser, localize_report)
    markers = driver.find_elements("css selector", "#matrix-svg circle.pair.match")
    assert len(markers) > 10
    marker = markers[len(markers) // 2]
    q, m = int(marker.get_attribute("data-i")), int(marker.get_attribute("data-j"))
    hover(driver, marker)
    wait_for(lambda: driver.find_element("id", "pair-viewer").get_attribute("data-i") == str(q), "the match")
    thumbs = shown_thumbnails(driver, "#pair-viewer")
    assert [t[0] for t in thumbs] == [str(q), str(m)] and all(t[1] > 20 for t in thumbs), thumbs
    text = driver.find_element("id", "pair-viewer").text
    # The query is the corridor's second walk (41.jpg ...), the map its first (1.jpg ...).
    assert "query frame %d (%d.jpg)" % (q, q + 41) in text and "map frame %d (%d.jpg)" % (m, m + 1) in text, text
    hover(driver, driver.find_element("css selector", "#pr-svg rect.overlay"))
    readout = driver.find_element("id", "pr-readout").text
    assert "seqtopo alignment" in readout and "single frame" in readout, readout
    classes = [p.get_attribute("class") for p in driver.find_elements("css selector", "#pr-svg path.curve")]
    assert classes[-1] == "curve primary", classes
    save_screenshot(driver, "localize-match")
    assert not console_errors(driver)


def test_descriptor_input_says_there_are_no_images(browser, scratch):
    from PIL import Image

    # The corridor's patch thumbnails as descriptors.npy: a map without images to show.
    folder = os.path.join(DATA, "rtabmap-corridor")
    rows = [np.asarray(Image.open(os.path.join(folder, "%d.jpg" % k)).convert("L").resize((16, 12)), dtype=np.float32)
            .ravel() for k in range(1, 85)]
    path = os.path.join(scratch, "descriptors.npy")
    np.save(path, np.stack(rows))
    out = os.path.join(scratch, "npy-map")
    run_seqtopo(["map", path, "--out", out, "--threshold", "5"], cwd=scratch)
    report = os.path.join(out, "report.html")
    with open(report, encoding="utf-8") as f:
        assert "no images: the input is a descriptors.npy" in f.read()
    driver = open_report(browser, report)
    cells = driver.find_element("css selector", "#matrix-svg image.matrix-image")
    from selenium.webdriver.common.action_chains import ActionChains
    driver.execute_script("arguments[0].scrollIntoView({block: 'center'})", cells)
    ActionChains(driver).move_to_element_with_offset(cells, 10, 40).click().perform()
    panel = driver.find_element("id", "pair-viewer")
    wait_for(lambda: panel.get_attribute("data-kind") in ("cell", "pair"), "the clicked cell")
    assert "no images: the input is a descriptors.npy" in panel.text
    assert not driver.find_elements("css selector", "#pair-viewer img")
    assert not console_errors(driver)


def test_without_d3_the_report_is_static_and_says_so(browser, scratch):
    out = os.path.join(scratch, "no-d3")
    r = run_seqtopo(["map", "--out", out], cwd=scratch, env={"SEQTOPO_D3_JS": "/nonexistent/d3.min.js"})
    warnings = [l for l in r.stderr.splitlines() if "warning" in l]
    assert warnings == ["seqtopo map: warning: /nonexistent/d3.min.js not found (Debian package libjs-d3, installed "
                        "by scripts/setup.sh): report.html is static, without its interactive views"], r.stderr
    report = os.path.join(out, "report.html")
    with open(report, encoding="utf-8") as f:
        html = f.read()
    assert "<script" not in html and 'id="static-note"' in html
    problems = report_check.check_report(browser, report, "seqtopo map: ", ("Summary", "Parameters"),
                                         ("pr_curve.png", "similarity.png", "topology.svg"), min_images=3)
    assert not problems, problems


def test_the_static_figures_have_axes_colour_bar_and_legends(map_report):
    """The PNGs `seqtopo map` wrote for the corridor, checked on their pixels."""
    from PIL import Image

    folder = os.path.dirname(map_report)
    a = np.asarray(Image.open(os.path.join(folder, "similarity.png")).convert("RGB")).astype(int)
    grey = a.mean(axis=2)
    dark = grey < 60
    # The matrix's frame: the longest dark row and column; the image inside is 84 cells drawn as squares.
    rows = dark.sum(axis=1)
    cols = dark.sum(axis=0)
    frame_bottom = int(np.flatnonzero(rows >= 0.6 * rows.max())[-1])
    frame_left = int(np.flatnonzero(cols >= 0.6 * cols.max())[0])
    # Tick marks below the frame: short dark runs in the 7 rows under it, at 5 or more separate columns.
    below = dark[frame_bottom + 2:frame_bottom + 7, frame_left:]
    tick_columns = np.flatnonzero(below.sum(axis=0) >= 4)
    groups = np.split(tick_columns, np.flatnonzero(np.diff(tick_columns) > 3) + 1)
    assert len(groups) >= 5, "tick marks below the matrix at %r" % tick_columns
    # Tick marks left of the frame too.
    left = dark[:frame_bottom, frame_left - 9:frame_left - 2]
    assert len(np.split(np.flatnonzero(left.sum(axis=1) >= 4),
                        np.flatnonzero(np.diff(np.flatnonzero(left.sum(axis=1) >= 4)) > 3) + 1)) >= 5
    # The colour bar: a column right of the matrix whose grey falls from white to black, through 100+ levels.
    bars = []
    for x in range(frame_left + 100, a.shape[1]):
        column = grey[:frame_bottom, x]
        equal = (a[:frame_bottom, x, 0] == a[:frame_bottom, x, 1]) & (a[:frame_bottom, x, 1] == a[:frame_bottom, x, 2])
        values = column[equal & (column > 0) & (column < 255)]
        if len(np.unique(values)) >= 100 and np.all(np.diff(values) <= 2) and values[0] > 230 and values[-1] < 25:
            bars.append(x)
    assert bars, "no white-to-black colour bar right of the matrix"
    # The legend below: the kept (red) and pruned (blue) entries.
    legend = a[frame_bottom + 40:]
    for rgb in ((255, 30, 30), (40, 110, 255)):
        assert (np.abs(legend - rgb).max(axis=2) < 40).sum() > 20, "no legend entry in %r" % (rgb,)

    p = np.asarray(Image.open(os.path.join(folder, "pr_curve.png")).convert("RGB")).astype(int)
    red = np.abs(p - (220, 30, 30)).max(axis=2) < 40
    frame = (p.mean(axis=2) < 60).sum(axis=1)
    top = int(np.flatnonzero(frame >= 0.6 * frame.max())[0])
    # The corridor's curve is at precision 1.0: drawn below the frame's top line, not on it.
    red_rows = np.flatnonzero(red.sum(axis=1) > 50)
    assert len(red_rows) and red_rows.min() >= top + 8, (top, red_rows[:5])
    blue = np.abs(p - (40, 90, 220)).max(axis=2) < 40
    assert blue.sum() > 100, "no baseline curve or legend entry"
