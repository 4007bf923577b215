"""``sielaff report``: one self-contained page, checked by a parser and in a real browser.

Five pages are made once a session (the example deck, an SI spec, a double crank, the
sweep spec and the synthesis spec) and every test reads them: the first in the
default tier, the other four (about 7 s of CPU a page) in the slow tier, each set in
one process.  The browser test opens
each in Debian's headless Chromium through Playwright (the ``browser`` extra; ``.ci/run``
installs both), one browser for all, and skips, saying why, where either is missing.  It
checks that the page loads with no console error, that no request leaves it, that every
image decodes, and that a screenshot is a rendered page: not blank, with the title's
text drawn where the title is.
"""

from __future__ import annotations

import base64
import html.parser
import io
import os
import subprocess
import sys

import numpy as np
import pytest

import procs
from conftest import DECKS, tiered

pytest.importorskip("matplotlib")

VOID = {"meta", "img", "br", "hr", "link", "input", "source", "col", "area", "base", "wbr"}

IN, LB, ZI = 0.0254, 0.45359237, 0.1129848290276167  # m/in, kg/lb, kg m^2 per in-lb-sec^2

SI_SPEC = f"""
[weights]
crank = {3 * LB:.4f}
coupler = {8 * LB:.4f}
rocker = {6 * LB:.4f}
[inertia]
crank = 0.0
coupler = {0.5 * ZI:.4f}
rocker = {0.4 * ZI:.4f}
[lengths]
frame = {12 * IN:.4f}
crank = {4 * IN:.4f}
coupler = {16 * IN:.4f}
rocker = {12 * IN:.4f}
[mass_centres]
crank = {{ distance = {2 * IN:.4f}, angle = 0.0 }}
coupler = {{ distance = {8 * IN:.4f}, angle = -15.0 }}
rocker = {{ distance = {6 * IN:.4f}, angle = 15.0 }}
[drive]
speed = 50.0
[[range]]
start = 10.0
step = 10.0
stop = 360.0
[scene]
units = "SI"
gravity = "down"
"""

#: A double crank: the frame is the shortest link (4 + 16 < 12 + 12).
DOUBLE_CRANK = """\
    3.0     8.0     6.0
    0.0     0.5     0.4
    4.0    12.0    16.0    12.0
    0.0   -15.0    15.0
    2.0     8.0     6.0
   50.0
   10.0    10.0   360.0
"""


def _cli(*args: str, cwd=None) -> subprocess.CompletedProcess:
    return procs.run(args, text=True, timeout=900, cwd=cwd)


#: The pages the tests read, each made once a session: (name, input, its suffix).
PAGES = (("example", "example.dat"), ("si", "si.toml"), ("double", "double.dat"),
         ("sweep", "sweep.toml"), ("synth", "synth.toml"))
#: The pages of the default tier; the others are made only for the slow tier's tests.
DEFAULT_PAGES = ("example",)


#: The frames of the page's animation (report.py draws 24).
FRAMES = 24


#: Makes each page ``sielaff report SRC -o OUT`` as the command line does (``cli.main``,
#: which restores the warning filters and the signals after each run), all in one
#: process: the imports are paid once, not once a page; prints each exit status.
MAKE_PAGES = """
import sys
from sielaff import cli
for src, out in zip(sys.argv[1::2], sys.argv[2::2]):
    print(cli.main(["report", src, "-o", out]), flush=True)
"""


def _make_pages(tmp_path_factory, names) -> dict[str, str]:
    """Pages of ``names`` (of the example deck, an SI spec, a double crank, the sweep
    spec and the synthesis spec), made in one process by the command's entry point;
    nothing may reach stderr (no warning, no message)."""
    d = tmp_path_factory.mktemp("report")
    (d / "si.toml").write_text(SI_SPEC)
    (d / "double.dat").write_text(DOUBLE_CRANK)
    sources = {"example": DECKS / "example.dat", "si": d / "si.toml",
               "double": d / "double.dat", "sweep": DECKS / "sweep.toml",
               "synth": DECKS / "synth.toml"}
    out = {name: str(d / f"{name}.html") for name in names}
    argv = [str(x) for name in names for x in (sources[name], out[name])]
    r = subprocess.run([sys.executable, "-c", MAKE_PAGES, *argv], capture_output=True,
                       text=True, timeout=900)
    assert r.returncode == 0 and r.stdout.split() == ["0"] * len(names), r.stdout + r.stderr
    assert r.stderr == "", r.stderr
    return out


@pytest.fixture(scope="session")
def pages(tmp_path_factory) -> dict[str, str]:
    """The default tier's page: the example deck."""
    return _make_pages(tmp_path_factory, DEFAULT_PAGES)


@pytest.fixture(scope="session")
def slow_pages(tmp_path_factory) -> dict[str, str]:
    """The slow tier's pages: the SI spec, the double crank, the sweep and synthesis specs."""
    return _make_pages(tmp_path_factory,
                       [n for n, _ in PAGES if n not in DEFAULT_PAGES])


def _page(request, name: str) -> str:
    """The page ``name``, from the fixture of its tier (the slow one made only if asked)."""
    return request.getfixturevalue("pages" if name in DEFAULT_PAGES else "slow_pages")[name]


class _Checker(html.parser.HTMLParser):
    """A strict walk: every element closed in order, every image a data: URI, no link to
    anything outside the page."""

    def __init__(self) -> None:
        super().__init__(convert_charrefs=True)
        self.stack: list[str] = []
        self.images: list[str] = []
        self.problems: list[str] = []
        self.text: list[str] = []
        self.doctype = False

    def handle_decl(self, decl: str) -> None:
        self.doctype = self.doctype or decl.lower() == "doctype html"

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        for key in ("src", "href", "action", "poster"):
            if key in a and not (a[key] or "").startswith("data:"):
                self.problems.append(f"<{tag} {key}={a[key]!r}> points outside the page")
        if tag == "img":
            self.images.append(a.get("src", ""))
            if not a.get("alt"):
                self.problems.append("an image without alt text")
        if tag == "script":
            self.problems.append("a script")
        if tag not in VOID:
            self.stack.append(tag)

    def handle_endtag(self, tag):
        if not self.stack or self.stack[-1] != tag:
            self.problems.append(f"</{tag}> closes <{self.stack[-1] if self.stack else ''}>")
        else:
            self.stack.pop()

    def handle_data(self, data):
        self.text.append(data)


def _check(path: str) -> _Checker:
    c = _Checker()
    with open(path, encoding="utf-8") as f:
        c.feed(f.read())
    c.close()
    assert c.doctype and not c.stack and not c.problems, (c.stack, c.problems)
    return c


@pytest.mark.parametrize("name", tiered([n for n, _ in PAGES], DEFAULT_PAGES))
def test_the_page_is_valid_html_and_self_contained(request, name):
    import matplotlib.image
    from PIL import Image

    c = _check(_page(request, name))
    assert len(c.images) >= 2  # the linkage and its animation, or a ranking's two pictures
    gifs = 0
    for src in c.images:
        mime, _, data = src.partition(";base64,")
        raw = base64.b64decode(data, validate=True)
        fmt = {"data:image/png": "png", "data:image/gif": "gif"}[mime]
        if fmt == "png":
            img = matplotlib.image.imread(io.BytesIO(raw), format="png")
            assert img.shape[0] > 100 and img.shape[1] > 100
        else:
            gifs += 1
            assert raw[:6] in (b"GIF87a", b"GIF89a") and raw[-1:] == b";"
            with Image.open(io.BytesIO(raw)) as im:  # one cycle: every frame moves
                assert im.n_frames == FRAMES
                frames = []
                for k in range(im.n_frames):
                    im.seek(k)
                    frames.append(np.asarray(im.convert("RGB"), dtype=float))
            assert all(np.abs(a - b).max() > 100 for a, b in zip(frames, frames[1:]))
            assert all(f.std() > 10 for f in frames)  # drawn, not blank
    assert gifs == (0 if name == "synth" else 1)
    text = " ".join(" ".join(c.text).split())
    assert "sielaff report" in text and "Made by sielaff" in text


def test_the_example_page_holds_what_a_colleague_needs(pages):
    text = " ".join(" ".join(_check(pages["example"]).text).split())
    for needed in ("A crank-rocker in in-lb-sec units", "Peaks", "driving torque, largest",
                   "in-lb", "Figures", "Fig. 12", "The check report", "Grashof",
                   "1966 quirk", "flywheel", "Balancing", "Counterweights",
                   "sielaff report " + str(DECKS / "example.dat")):
        assert needed in text, needed


@pytest.mark.slow
def test_the_si_page_is_in_si(slow_pages):
    text = " ".join(" ".join(_check(slow_pages["si"]).text).split())
    assert "in SI units" in text and "gravity" in text
    peaks = text[text.index("Peaks"):text.index("Figures")]
    assert " N m " in peaks and " N " in peaks and " in-lb " not in peaks and " lb " not in peaks


@pytest.mark.slow
def test_the_double_crank_page_names_its_kind(slow_pages):
    text = " ".join(" ".join(_check(slow_pages["double"]).text).split())
    assert "A double-crank" in text and "Peaks" in text


def test_bad_input_is_one_line_and_leaves_no_page(tmp_path, capsys):
    from sielaff import cli

    target = tmp_path / "r.html"

    def report(*args: str) -> tuple[int, str]:
        status = cli.main(["report", *args, "-o", str(target)])
        return status, capsys.readouterr().err

    status, err = report(str(tmp_path / "missing.dat"))
    assert status == 2 and err.count("\n") == 1 and "missing.dat" in err
    assert not target.exists()
    (tmp_path / "bad.dat").write_text("    3.0     8.0\n")
    status, err = report(str(tmp_path / "bad.dat"))
    assert status == 2 and err.count("\n") == 1 and "Traceback" not in err
    assert not target.exists() and os.listdir(tmp_path) == ["bad.dat"]
    # a synthesis spec: its reader's one line; --branch is each candidate's own
    bad = (DECKS / "synth.toml").read_text().replace('problem = "crank_rocker"',
                                                     'problem = "cam"')
    (tmp_path / "bad.toml").write_text(bad)
    status, err = report(str(tmp_path / "bad.toml"))
    assert status == 2 and err.count("\n") == 1 and "[synthesis] problem" in err
    status, err = report(str(DECKS / "synth.toml"), "--branch", "open")
    assert status == 2 and err.count("\n") == 1 and "--branch" in err
    assert not target.exists() and sorted(os.listdir(tmp_path)) == ["bad.dat", "bad.toml"]


def test_bad_input_from_the_command_line(tmp_path):
    """The same as a user meets it: a process, its exit status, one line, no traceback."""
    target = tmp_path / "r.html"
    (tmp_path / "bad.dat").write_text("    3.0     8.0\n")
    r = _cli("report", str(tmp_path / "bad.dat"), "-o", str(target))
    assert r.returncode == 2 and r.stderr.count("\n") == 1 and "Traceback" not in r.stderr
    assert "bad.dat" in r.stderr and not target.exists()


def test_a_failure_while_writing_leaves_the_old_page(tmp_path, monkeypatch, capsys):
    from sielaff import cli
    from sielaff.tools import report

    target = tmp_path / "r.html"
    target.write_text("old page")

    def broken(*args, **kwargs):
        raise OSError(28, "No space left on device", str(target))

    monkeypatch.setattr(report, "report_html", broken)
    assert cli.main(["report", str(DECKS / "example.dat"), "-o", str(target)]) == 2
    assert target.read_text() == "old page"
    assert os.listdir(tmp_path) == ["r.html"]
    assert capsys.readouterr().err.count("\n") == 1


# ----- in a real browser ---------------------------------------------------------------

# the browser fixture (Debian's chromium through Playwright) is conftest.py's


@pytest.mark.parametrize("name", tiered([n for n, _ in PAGES], DEFAULT_PAGES))
def test_the_page_in_a_browser(request, browser, name, tmp_path):
    page = browser.new_page(viewport={"width": 1100, "height": 900})
    errors, requests = [], []
    page.on("console", lambda m: errors.append(m.text) if m.type == "error" else None)
    page.on("pageerror", lambda e: errors.append(str(e)))
    url = "file://" + os.path.abspath(_page(request, name))
    page.on("request", lambda r: requests.append(r.url)
            if not (r.url == url or r.url.startswith("data:")) else None)
    page.goto(url, wait_until="load")
    assert errors == [] and requests == [], (errors, requests)
    images = page.eval_on_selector_all(
        "img", "els => els.map(e => [e.complete, e.naturalWidth, e.naturalHeight])")
    assert len(images) >= 2 and all(c and w > 0 and h > 0 for c, w, h in images), images
    assert page.title() == "sielaff report: " + dict(PAGES)[name]
    shot = tmp_path / "shot.png"
    page.screenshot(path=str(shot))
    box = page.locator("h1").bounding_box()
    page.close()
    import matplotlib.image

    pixels = matplotlib.image.imread(str(shot))[..., :3]
    assert pixels.std() > 0.05  # not blank: text, lines and pictures
    x0, y0 = int(box["x"]), int(box["y"])
    title = pixels[y0:y0 + int(box["height"]), x0:x0 + int(box["width"])]
    dark = np.count_nonzero(title.mean(axis=-1) < 0.5)
    assert dark > 200, "the title's text is not drawn where the h1 is"


@pytest.mark.slow
def test_a_sweep_spec_gets_its_pareto_front(slow_pages):
    """decks/sweep.toml: the page holds the sweep's Pareto front, checked against the
    front computed here from the sweep's own figures."""
    from sielaff.design.figures import figures
    from sielaff.tools.common import read_spec_deck

    c = _check(slow_pages["sweep"])
    text = " ".join(" ".join(c.text).split())
    assert "The sweep" in text and "5,002 designs (61 x 41 x 2" in text
    assert "Pareto front of TORQ_RMS and SHAK_PEAK" in text
    # the first row of the front: the design with the least TORQ_RMS
    deck, scene = read_spec_deck(str(DECKS / "sweep.toml"))
    R4, W3 = np.meshgrid(np.linspace(9.0, 15.0, 61), np.linspace(2.0, 12.0, 41), indexing="ij")
    f = figures(deck.mechanism.replace(R4=R4.ravel(), W3=W3.ravel()), scene=scene)
    best = np.nanmin(f["TORQ_RMS"])  # unbalanced designs; balanced ones only add torque
    row = text[text.index("TORQ_RMS [in-lb] SHAK_PEAK [lb]"):]
    assert f"{best:.5g}" in row.split("The sweep's designs")[0]


class _Table(html.parser.HTMLParser):
    """The cells of a page's tables, row by row (one list of rows per table)."""

    def __init__(self) -> None:
        super().__init__(convert_charrefs=True)
        self.tables: list[list[list[str]]] = []
        self.cell: list[str] | None = None

    def handle_starttag(self, tag, attrs):
        if tag == "table":
            self.tables.append([])
        elif tag == "tr":
            self.tables[-1].append([])
        elif tag in ("td", "th"):
            self.cell = []

    def handle_endtag(self, tag):
        if tag in ("td", "th") and self.cell is not None:
            self.tables[-1][-1].append("".join(self.cell).strip())
            self.cell = None

    def handle_data(self, data):
        if self.cell is not None:
            self.cell.append(data)


@pytest.mark.slow
def test_a_synthesis_spec_gets_its_ranking(slow_pages):
    """decks/synth.toml: the ranking table, best first, is the ranking computed here
    through the synthesis API (not the spec reader): the same candidates in the same
    order with the same figures, the units in the headers, the front marked."""
    from sielaff import Scene, synthesis

    text = " ".join(" ".join(_check(slow_pages["synth"]).text).split())
    assert "A synthesis (crank_rocker) in in-lb-sec units" in text
    assert "32 candidates from 2 problems (0 without a solution): all crank-rockers" in text
    assert "The best candidates" in text and "[synthesis.crank_rocker]" in text  # the spec
    families = [synthesis.crank_rocker(45.0, q, rocker=10.0, th2d=10.0).members(8)
                for q in (1.15, 1.25)]  # [synthesis.vary] time_ratio: problems 0 and 1
    cands = families[0] + families[1]
    origin = [0] * len(families[0]) + [1] * len(families[1])
    r = synthesis.rank(cands, scene=Scene(tex=-50.0), by=["TORQ_PEAK", "SHAK_PEAK"],
                       pareto=["TORQ_RMS", "GAMMA_MIN"])
    t = _Table()
    with open(slow_pages["synth"], encoding="utf-8") as f:
        t.feed(f.read())
    table = next(tb for tb in t.tables if tb[0][:2] == ["rank", "cand."])
    head, rows = table[0], table[1:]
    assert head == ["rank", "cand.", "time_ratio", "k", "side", "branch", "R1 [in]",
                    "R2 [in]", "R3 [in]", "R4 [in]", "TORQ_PEAK [in-lb]", "SHAK_PEAK [lb]",
                    "TORQ_RMS [in-lb]", "GAMMA_MIN [deg]", "Pareto"]
    assert len(rows) == 20
    front = {int(i) for i in r.pareto}
    for row, i in zip(rows, r.order):
        cell = dict(zip(head, row))
        assert cell["rank"] == str(r.ranks[i]) and cell["cand."] == str(int(i))
        # each row names what it came from: the varied time ratio, k and side
        assert cell["time_ratio"] == f"{(1.15, 1.25)[origin[i]]:.4g}"
        assert cell["k"] == f"{cands[i].k:.4g}" and cell["side"] == cands[i].side
        assert cell["branch"] == r.branches[i]
        assert cell["R2 [in]"] == f"{r.mechanisms[i].R2:.5g}"
        for fig, u in (("TORQ_PEAK", "in-lb"), ("SHAK_PEAK", "lb"), ("GAMMA_MIN", "deg")):
            assert cell[f"{fig} [{u}]"] == f"{r.figures[fig][i]:.5g}"
        assert cell["Pareto"] == ("yes" if int(i) in front else "")


def test_a_tolerance_spec_gets_its_table(tmp_path, monkeypatch, capsys):
    """A spec with a [tolerance] gets the study ``sielaff tolerance`` prints: the page's
    section is that command's output (a small study, made here twice), and the report
    reads such a spec's mechanism and scene."""
    from sielaff import cli
    from sielaff.tools import report

    spec = tmp_path / "tol.toml"
    spec.write_text((DECKS / "tolerance.toml").read_text().replace("n = 2000", "n = 40"))
    seen = {}

    def page(deck, scene, command, at=None, tolerances=None, motor=None):
        seen.update(deck=deck, scene=scene, tolerances=tolerances)
        return "<!DOCTYPE html>\n"

    monkeypatch.setattr(report, "report_html", page)
    assert cli.main(["report", str(spec), "-o", str(tmp_path / "t.html")]) == 0
    assert seen["deck"].mechanism.R1 == 12.0 and seen["scene"].tex == -200.0
    assert seen["tolerances"]["n"] == 40 and seen["tolerances"]["deviations"]["W3"] == 0.1
    section = report.tolerance_section(seen["deck"], seen["scene"], seen["tolerances"])
    capsys.readouterr()
    assert cli.main(["tolerance", str(spec)]) == 0
    printed = capsys.readouterr().out
    assert section[0] == "<h2>Tolerances</h2>"
    assert html.unescape(section[1]) == "<pre>" + printed.rstrip("\n") + "</pre>"
    assert "TORQ_PEAK   in-lb" in printed and "per in R1" in printed


def test_the_si_peaks_and_scene_carry_si_units():
    """The default tier's guard of the report's units (the whole SI page is the slow
    tier's): the peaks table and the scene section of decks/si.toml, made by the report's
    own functions, name SI units only."""
    from sielaff.tools.common import read_spec_deck
    from sielaff.tools.report import peak_rows, scene_section
    from sielaff.tools.report import peaks_table as _peaks_table
    from test_units import REPORT_UNIT

    deck, scene = read_spec_deck(str(DECKS / "si.toml"))
    assert deck.mechanism.units == "SI"
    rows = peak_rows(deck, scene, n=360)
    assert len(rows) >= 4
    units = {p.unit for p in rows}
    assert "N m" in units and "N" in units
    assert units <= {"N", "N m", "m/s", "m/s^2", "rad/s", "rad/s^2", "deg", "W", "-"}
    table = _peaks_table(rows)
    assert REPORT_UNIT.search(table) is None, REPORT_UNIT.search(table)
    section = "\n".join(scene_section(deck.mechanism, scene, True))
    assert scene.effects and "<h2>The scene</h2>" in section
    assert REPORT_UNIT.search(section) is None, REPORT_UNIT.search(section)
