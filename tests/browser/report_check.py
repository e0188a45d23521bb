"""Opens a seqtopo report.html in headless Chromium and lists what is wrong with it.

check_report() returns a list of problems (empty when the page is fine); each problem is one line that
starts with its kind in brackets, e.g. "[image] ...", so a test can say which check must fire.

The browser is started offline: a dead proxy (127.0.0.1:9) makes any network fetch fail at once and
visibly (console error and a failed request), and background services are switched off.
"""

import base64
import contextlib
import io
import json
import os
import re
import shutil
import signal
import tempfile
import time
import urllib.parse

CHROMEDRIVER = "/usr/bin/chromedriver"
# Debian's /usr/bin/chromium is a shell launcher that adds flags of its own (extensions, GPU
# rasterization); the browser binary it starts is used directly when it is there.
CHROMIUM_CANDIDATES = ("/usr/lib/chromium/chromium", "/usr/bin/chromium")

SETUP_HINT = ("the browser check needs Debian's chromium, chromium-driver, python3-selenium, python3-pil "
              "and python3-numpy, run with /usr/bin/python3 (scripts/setup.sh installs them)")


def missing_requirements():
    """What is missing to run the browser check (an empty list when everything is there)."""
    missing = []
    if not any(os.access(p, os.X_OK) for p in CHROMIUM_CANDIDATES):
        missing.append("chromium (" + " or ".join(CHROMIUM_CANDIDATES) + ")")
    if not os.access(CHROMEDRIVER, os.X_OK):
        missing.append("chromedriver (" + CHROMEDRIVER + ")")
    for module in ("selenium", "PIL", "numpy"):
        try:
            __import__(module)
        except ImportError:
            missing.append("python module " + module)
    return missing


def chromium_binary():
    return next(p for p in CHROMIUM_CANDIDATES if os.access(p, os.X_OK))


class Browser:
    """Headless Chromium driven by chromedriver, with a fresh profile in a temporary folder.

    Use as a context manager: on exit the browser quits, and any process still running with this
    browser's profile folder is reported in `leftover` (and ended, by its pid).
    """

    WIDTH, HEIGHT = 1280, 1000

    def __init__(self):
        self.driver = None
        self.leftover = []
        self._home = None

    def __enter__(self):
        from selenium import webdriver
        from selenium.webdriver.chrome.service import Service

        self._home = tempfile.mkdtemp(prefix="seqtopo-chromium-")
        self.profile = os.path.join(self._home, "profile")
        options = webdriver.ChromeOptions()
        options.binary_location = chromium_binary()
        for flag in (
            "--headless", "--no-sandbox", "--disable-gpu", "--user-data-dir=" + self.profile,
            # offline and quiet
            "--disable-background-networking", "--disable-component-update", "--disable-sync",
            "--no-first-run", "--disable-quic", "--proxy-server=127.0.0.1:9", "--proxy-bypass-list=<-loopback>",
            "--no-default-browser-check", "--disable-default-apps", "--disable-extensions",
            "--disable-breakpad", "--disable-crash-reporter", "--metrics-recording-only", "--mute-audio",
            # small /dev/shm in containers
            "--disable-dev-shm-usage",
            "--window-size=%d,%d" % (self.WIDTH, self.HEIGHT), "--force-device-scale-factor=1",
            "--hide-scrollbars",
        ):
            options.add_argument(flag)
        options.set_capability("goog:loggingPrefs", {"browser": "ALL", "performance": "ALL"})
        # chromedriver and Chromium keep their caches and configuration in the temporary folder too
        env = dict(os.environ, HOME=self._home, XDG_CONFIG_HOME=os.path.join(self._home, "config"),
                   XDG_CACHE_HOME=os.path.join(self._home, "cache"))
        service = Service(CHROMEDRIVER, env=env, log_path=os.path.join(self._home, "chromedriver.log"))
        try:
            self.driver = webdriver.Chrome(service=service, options=options)
        except Exception:
            self._cleanup()
            raise
        self.driver.set_page_load_timeout(30)
        self.driver.set_script_timeout(20)
        return self

    def __exit__(self, *exc):
        self._cleanup()
        return False

    def _cleanup(self):
        try:
            if self.driver is not None:
                self.driver.quit()
        finally:
            self.driver = None
            if self._home:
                self.leftover = _end_processes_using(self._home)
                shutil.rmtree(self._home, ignore_errors=True)
                self._home = None


def _processes_using(marker):
    """Pids of processes whose command line contains marker (here: this browser's temporary folder)."""
    pids = []
    for entry in os.listdir("/proc"):
        if not entry.isdigit() or int(entry) == os.getpid():
            continue
        try:
            with open("/proc/%s/cmdline" % entry, "rb") as f:
                cmdline = f.read().replace(b"\0", b" ").decode(errors="replace")
        except OSError:
            continue
        if marker in cmdline:
            pids.append((int(entry), cmdline[:120]))
    return pids


def _end_processes_using(marker, grace_seconds=5.0):
    """Waits for the browser's processes to exit after quit; ends (by pid) and returns any that stay."""
    deadline = time.monotonic() + grace_seconds
    while True:
        left = _processes_using(marker)
        if not left or time.monotonic() > deadline:
            break
        time.sleep(0.1)
    for pid, _ in left:
        with contextlib.suppress(OSError):
            os.kill(pid, signal.SIGKILL)
    return ["pid %d: %s" % (pid, cmd) for pid, cmd in left]


# ---- checks on the file itself --------------------------------------------------------------------

_URL_ATTRIBUTE = re.compile(r"""\b(?:src|href|xlink:href|srcset|poster|data|action)\s*=\s*(["']?)([^"'\s>]*)\1""", re.I)
_CSS_URL = re.compile(r"""url\(\s*(["']?)([^"')]*)\1\s*\)""", re.I)
_CSS_IMPORT = re.compile(r"""@import\s+(["'])([^"']*)\1""", re.I)
_DATA_URI = re.compile(r"""data:([\w/+.-]+)(;base64)?,([^"'\s)]*)""")


def _references(text):
    for pattern in (_URL_ATTRIBUTE, _CSS_URL, _CSS_IMPORT):
        for m in pattern.finditer(text):
            yield m.group(2)


def _is_local(reference):
    return reference.startswith("data:") or reference.startswith("#") or reference == ""


_IMG_SRC = re.compile(r"""<img\b[^>]*?\bsrc\s*=\s*(["'])(.*?)\1""", re.I | re.S)


def inlined_images(html):
    """(media type, decoded content or the exception) of every <img> in document order.

    A PNG/JPEG/GIF gives its (width, height), an SVG its text; an <img> whose source is not a data: URI
    gives (None, None).
    Each image is decoded completely here (PNG/JPEG/GIF pixels with PIL, SVG as XML), because a browser
    draws a truncated PNG as far as it goes and still reports it as loaded.
    """
    from PIL import Image
    import xml.etree.ElementTree as ElementTree

    images = []
    for m in _IMG_SRC.finditer(html):
        uri = _DATA_URI.fullmatch(m.group(2))
        if not uri:
            images.append((None, None))
            continue
        kind, is_base64, payload = uri.group(1), uri.group(2), uri.group(3)
        try:
            data = base64.b64decode(payload, validate=True) if is_base64 else urllib.parse.unquote_to_bytes(payload)
            if kind == "image/svg+xml":
                text = data.decode("utf-8")
                ElementTree.fromstring(text)
                images.append((kind, text))
            else:
                with Image.open(io.BytesIO(data)) as image:
                    image.load()
                    images.append((kind, image.size))
        except Exception as error:  # any decoding failure is a finding, reported with its message
            images.append((kind, error))
    return images


_SCRIPT = re.compile(r"<script\b[^>]*>(.*?)</script>", re.I | re.S)
# XML namespace names are identifiers that look like URLs (D3 and every SVG carry them); nothing fetches them.
_NAMESPACES = ("http://www.w3.org/2000/svg", "http://www.w3.org/1999/xhtml", "http://www.w3.org/1999/xlink",
               "http://www.w3.org/2000/xmlns/", "http://www.w3.org/XML/1998/namespace")


def static_problems(html, images=None):
    """Problems visible in the HTML text: anything referenced that is not inlined (also inside inlined
    SVG), and inlined images that do not decode. images: inlined_images(html) when already computed.
    Markup is searched for references (src=, href=, url(...)); scripts for URLs (other than XML namespace
    names), since code is no markup: what a script would fetch shows in the browser's network log."""
    problems = []
    if images is None:
        images = inlined_images(html)
    markup = _SCRIPT.sub("<script></script>", html)
    for ref in _references(markup):
        if not _is_local(ref):
            problems.append("[offline] the page references %s (everything must be inlined)" % ref[:100])
    for m in re.finditer(r"https?://[^\s\"'<>)]*", html):
        if m.group(0) not in _NAMESPACES:
            problems.append("[offline] the page text contains the URL %s" % m.group(0)[:100])
    for k, (kind, payload) in enumerate(images):
        if isinstance(payload, Exception):
            problems.append("[image] image %d (%s) does not decode outside the browser: %s" % (k, kind, payload))
        elif kind == "image/svg+xml":
            for ref in _references(payload):
                if not _is_local(ref):
                    problems.append("[offline] an inlined SVG references %s" % ref[:100])
    return problems


# ---- checks in the browser ------------------------------------------------------------------------

_IMAGES_SCRIPT = """
const done = arguments[arguments.length - 1];
const images = Array.from(document.images);
Promise.allSettled(images.map(i => i.decode())).then(results => done(images.map((img, k) => {
  const r = img.getBoundingClientRect();
  const caption = img.closest('figure') && img.closest('figure').querySelector('figcaption code');
  return {index: k, src: img.currentSrc.slice(0, 60), alt: img.alt, complete: img.complete,
          naturalWidth: img.naturalWidth, naturalHeight: img.naturalHeight,
          width: r.width, height: r.height, decoded: results[k].status === 'fulfilled',
          file: caption ? caption.textContent : ''};
})));
"""

_PAGE_SCRIPT = """
return {title: document.title,
        h1: Array.from(document.querySelectorAll('h1')).map(h => h.textContent.trim()),
        h2: Array.from(document.querySelectorAll('h2')).map(h => h.textContent.trim()),
        tables: document.querySelectorAll('table').length,
        scrollWidth: document.documentElement.scrollWidth, innerWidth: window.innerWidth,
        resources: performance.getEntriesByType('resource').map(e => e.name.slice(0, 100))};
"""


def pixel_variation(png_bytes, border=0):
    """(distinct colours, share of pixels that differ from the most common colour, luminance sd)."""
    import numpy as np
    from PIL import Image

    image = Image.open(io.BytesIO(png_bytes)).convert("RGB")
    a = np.asarray(image)
    if border and a.shape[0] > 2 * border and a.shape[1] > 2 * border:
        a = a[border:-border, border:-border]
    flat = a.reshape(-1, 3).astype(np.uint32)
    if flat.size == 0:
        return 0, 0.0, 0.0
    codes = (flat[:, 0] << 16) | (flat[:, 1] << 8) | flat[:, 2]
    values, counts = np.unique(codes, return_counts=True)
    other = 1.0 - counts.max() / codes.size
    luminance = a.astype(np.float64) @ np.array([0.299, 0.587, 0.114])
    return len(values), float(other), float(luminance.std())


def _blank_reason(png_bytes, border=0, min_colours=8, min_other=0.01, min_sd=3.0):
    colours, other, sd = pixel_variation(png_bytes, border)
    if colours < min_colours or other < min_other or sd < min_sd:
        return "%d colours, %.2f%% of pixels off the main colour, luminance sd %.1f" % (colours, 100 * other, sd)
    return None


def _network_problems(log, page_url):
    """Requests the page made (from the DevTools log): anything not inlined, and every failed load."""
    problems, urls, seen_page = [], {}, False
    for entry in log:
        message = json.loads(entry["message"])["message"]
        method, params = message.get("method", ""), message.get("params", {})
        if method == "Network.requestWillBeSent":
            url = params.get("request", {}).get("url", "")
            if params.get("documentURL") != page_url and url != page_url:
                continue  # the browser's own pages (new tab page), not the report
            urls[params.get("requestId")] = url
            seen_page = seen_page or url == page_url
            if url != page_url and not url.startswith("data:"):
                problems.append("[network] the page requested %s" % url[:100])
        elif method == "Network.loadingFailed" and params.get("requestId") in urls:
            problems.append("[network] loading %s failed: %s" % (urls[params["requestId"]][:100],
                                                                 params.get("errorText", "?")))
    if not seen_page:  # else the filter above would have hidden the page's own requests
        problems.append("[network] the DevTools log shows no request for %s" % page_url)
    return problems


def check_report(browser, path, title_prefix, headings=(), figures=(), min_images=1, artifacts=None):
    """Everything wrong with the report at path, as seen in the browser (an empty list when fine).

    title_prefix: the <title> and the <h1> must start with it; headings: <h2> texts (each must start one);
    figures: file names that some figure caption must name, with its image loaded; min_images: at least
    this many <img>. With artifacts (a folder), the screenshot is saved there when something is wrong.
    """
    driver = browser.driver
    path = os.path.abspath(path)
    with open(path, encoding="utf-8") as f:
        html = f.read()
    decoded = inlined_images(html)
    problems = static_problems(html, decoded)

    page_url = "file://" + urllib.parse.quote(path)
    driver.get_log("browser")  # drop what earlier pages logged
    driver.get_log("performance")
    driver.get(page_url)

    # A reader opens the folded sections (the static figures) to see them.
    driver.execute_script("document.querySelectorAll('details').forEach(d => d.open = true)")
    images = driver.execute_async_script(_IMAGES_SCRIPT)
    page = driver.execute_script(_PAGE_SCRIPT)

    # title and headings
    if not page["title"].startswith(title_prefix):
        problems.append("[heading] title is %r, expected it to start with %r" % (page["title"], title_prefix))
    if len(page["h1"]) != 1 or page["h1"][0] != page["title"]:
        problems.append("[heading] expected one <h1> equal to the title, found %r" % page["h1"])
    for heading in headings:
        if not any(h.startswith(heading) for h in page["h2"]):
            problems.append("[heading] no <h2> %r (headings: %r)" % (heading, page["h2"]))
    if page["tables"] == 0:
        problems.append("[heading] the page has no table")

    # images: loaded, decoded, shown at a readable size
    if len(images) < min_images:
        problems.append("[image] %d <img> on the page, expected at least %d" % (len(images), min_images))
    for img in images:
        name = img["file"] or img["alt"] or img["src"]
        if not (img["complete"] and img["naturalWidth"] > 0 and img["naturalHeight"] > 0 and img["decoded"]):
            problems.append("[image] image %d (%s) did not load: complete=%s naturalWidth=%s decoded=%s"
                            % (img["index"], name, img["complete"], img["naturalWidth"], img["decoded"]))
        elif (img["index"] < len(decoded) and isinstance(decoded[img["index"]][1], tuple)
              and tuple(decoded[img["index"]][1]) != (img["naturalWidth"], img["naturalHeight"])):
            problems.append("[image] image %d (%s) is %dx%d in the browser but %dx%d in the file"
                            % (img["index"], name, img["naturalWidth"], img["naturalHeight"], *decoded[img["index"]][1]))
        elif img["width"] < 100 or img["height"] < 100:
            problems.append("[image] image %d (%s) is shown at %.0fx%.0f px" % (img["index"], name, img["width"], img["height"]))
        if not img["alt"]:
            problems.append("[image] image %d (%s) has no alt text" % (img["index"], name))
    for name in figures:
        if not any(img["file"] == name for img in images):
            problems.append("[image] no figure for %s (captions: %r)" % (name, [i["file"] for i in images]))
    if page["scrollWidth"] > page["innerWidth"]:
        problems.append("[layout] the page is %d px wide in a %d px window" % (page["scrollWidth"], page["innerWidth"]))

    # console and network
    for entry in driver.get_log("browser"):
        if entry.get("level") == "SEVERE":
            problems.append("[console] %s" % entry.get("message", "")[:300])
    for name in page["resources"]:
        if not name.startswith("data:"):
            problems.append("[network] resource timing lists %s" % name)
    problems += _network_problems(driver.get_log("performance"), page_url)

    # pixels: the visible page and every figure on it are not blank
    shot = driver.get_screenshot_as_png()
    reason = _blank_reason(shot)
    if reason:
        problems.append("[blank] the page screenshot is blank: " + reason)
    elements = driver.find_elements("tag name", "img")
    for img, element in zip(images, elements):
        if not img["naturalWidth"] or img["width"] < 10 or img["height"] < 10:
            continue  # already reported
        driver.execute_script("arguments[0].scrollIntoView({block: 'center'})", element)
        reason = _blank_reason(element.screenshot_as_png, border=3)
        if reason:
            problems.append("[blank] image %d (%s) shows nothing: %s" % (img["index"], img["file"] or img["alt"], reason))

    if problems and artifacts:
        os.makedirs(artifacts, exist_ok=True)
        stem = os.path.join(artifacts, os.path.basename(os.path.dirname(path)) + "-" + os.path.basename(path))
        with open(stem + ".png", "wb") as f:
            f.write(shot)
        shutil.copyfile(path, stem)
        problems.append("(screenshot and page saved as %s.png and %s)" % (stem, stem))
    return problems
