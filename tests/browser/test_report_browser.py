"""The HTML reports of `seqtopo map` and `seqtopo localize`, opened in headless Chromium.

Run by ctest (tests/CMakeLists.txt) as
  /usr/bin/python3 -m pytest -c tests/browser/pytest.ini tests/browser
with SEQTOPO_CLI (the seqtopo binary) and SEQTOPO_DATA_DIR (the bundled data/) in the environment.

The first tests make real reports and require the browser to find nothing wrong; the others break a copy
of a real report in one way each and require the checker to say so, so that a passing run means something.
Chromium is required: without it the tests fail (scripts/setup.sh installs it), they never skip.
"""

import base64
import io
import os
import re

import pytest

import report_check
from conftest import ARTIFACTS

MAP_HEADINGS = ("Summary", "Loop-closure accuracy", "Similarity matrix and alignments", "Topological map", "Parameters")
MAP_FIGURES = ("pr_curve.png", "similarity.png", "topology.svg")
LOCALIZE_HEADINGS = ("Summary", "Localization accuracy", "Similarity matrix", "Parameters")
LOCALIZE_FIGURES = ("pr_curve.png", "similarity.png")


def assert_clean(problems, what):
    if problems:
        pytest.fail("%s, as Chromium shows it:\n  %s" % (what, "\n  ".join(problems)), pytrace=False)


def test_map_report_shows_in_the_browser(browser, map_report):
    problems = report_check.check_report(browser, map_report, "seqtopo map: ", MAP_HEADINGS, MAP_FIGURES,
                                         min_images=3, artifacts=ARTIFACTS)
    assert_clean(problems, "seqtopo map's report.html")


def test_localize_report_shows_in_the_browser(browser, localize_report):
    problems = report_check.check_report(browser, localize_report, "seqtopo localize: ", LOCALIZE_HEADINGS,
                                         LOCALIZE_FIGURES, min_images=2, artifacts=ARTIFACTS)
    assert_clean(problems, "seqtopo localize's report.html")


# ---- the checker itself must fail on broken pages -------------------------------------------------

def broken_copy(report, scratch, name, edit):
    with open(report, encoding="utf-8") as f:
        html = f.read()
    changed = edit(html)
    assert changed != html, "the edit for %s changed nothing" % name
    path = os.path.join(scratch, "broken", name + ".html")
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w", encoding="utf-8") as f:
        f.write(changed)
    return path


def kinds(problems):
    return {m.group(1) for m in (re.match(r"\[(\w+)\]", p) for p in problems) if m}


def check_map_copy(browser, path):
    return report_check.check_report(browser, path, "seqtopo map: ", MAP_HEADINGS, MAP_FIGURES, min_images=3)


def cut_data_uri(media_type, keep):
    """An edit that cuts the first data: URI of media_type; keep(n) gives the base64 characters kept."""
    def edit(html):
        start = html.index("data:%s;base64," % media_type) + len("data:%s;base64," % media_type)
        end = html.index('"', start)
        return html[:start] + html[start:end][:keep(end - start)] + html[end:]
    return edit


@pytest.mark.parametrize("name, edit, index, browser_sees_it", [
    # a PNG cut in the middle (on a base64 boundary): Chromium draws the top part and calls it loaded,
    # so only the full decode of the file catches it
    pytest.param("png-cut-in-half", cut_data_uri("image/png", lambda n: n // 8 * 4), 0, False, id="png-cut-in-half"),
    pytest.param("png-header-only", cut_data_uri("image/png", lambda n: 40), 0, True, id="png-header-only"),
    pytest.param("svg-cut-in-half", cut_data_uri("image/svg+xml", lambda n: n // 8 * 4), 2, True, id="svg-cut-in-half"),
])
def test_checker_fails_on_a_truncated_image(browser, map_report, scratch, name, edit, index, browser_sees_it):
    problems = check_map_copy(browser, broken_copy(map_report, scratch, name, edit))
    assert kinds(problems) == {"image"}, problems
    assert any(p.startswith("[image] image %d " % index) and "does not decode" in p for p in problems), problems
    assert browser_sees_it == any("did not load" in p for p in problems), problems


def test_checker_fails_on_an_external_image(browser, map_report, scratch):
    external = '<figure><img alt="remote" src="http://example.com/figure.png"></figure>\n</body>'
    problems = check_map_copy(browser, broken_copy(map_report, scratch, "external-image",
                                                   lambda h: h.replace("</body>", external)))
    # seen in the text, refused by the offline browser (console and network), and not loaded
    assert {"offline", "console", "network", "image"} <= kinds(problems), problems


def test_checker_fails_on_a_script_error(browser, map_report, scratch):
    problems = check_map_copy(browser, broken_copy(map_report, scratch, "script-error",
                                                   lambda h: h.replace("</body>", "<script>undefinedFunction()</script></body>")))
    assert kinds(problems) == {"console"}, problems


def test_checker_fails_on_a_blank_page(browser, map_report, scratch):
    problems = check_map_copy(browser, broken_copy(map_report, scratch, "blank-page",
                                                   lambda h: h.replace("</style>", "body{visibility:hidden}</style>")))
    assert kinds(problems) == {"blank"}, problems
    assert any("page screenshot" in p for p in problems), problems


def test_checker_fails_on_a_blank_figure(browser, map_report, scratch):
    from PIL import Image

    png = io.BytesIO()
    Image.new("RGB", (400, 300), "white").save(png, "PNG")
    white = "data:image/png;base64," + base64.b64encode(png.getvalue()).decode()

    def replace_first_png(html):
        start = html.index("data:image/png;base64,")
        return html[:start] + white + html[html.index('"', start):]

    problems = check_map_copy(browser, broken_copy(map_report, scratch, "blank-figure", replace_first_png))
    assert kinds(problems) == {"blank"}, problems
    assert any("pr_curve.png" in p for p in problems), problems


def test_checker_fails_without_title_and_headings(browser, map_report, scratch):
    def strip(html):
        html = re.sub(r"<title>[^<]*</title>", "<title></title>", html)
        return re.sub(r"<h[12]>[^<]*</h[12]>", "", html)

    problems = check_map_copy(browser, broken_copy(map_report, scratch, "no-headings", strip))
    assert kinds(problems) == {"heading"}, problems


def test_checker_fails_on_a_missing_figure(browser, map_report, scratch):
    def drop_topology(html):
        return re.sub(r"<figure><img[^>]*svg\+xml[^>]*>.*?</figure>", "", html, count=1, flags=re.S)

    problems = check_map_copy(browser, broken_copy(map_report, scratch, "missing-figure", drop_topology))
    assert any("2 <img>" in p for p in problems) and any("topology.svg" in p for p in problems), problems
