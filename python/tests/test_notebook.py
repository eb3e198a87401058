"""The tour notebook (examples/python/tour.ipynb) runs in a real Jupyter kernel, every
cell without error, and shows its figure and its replays inline.

Needs nbclient, nbconvert and ipykernel (`pip install nbclient nbconvert ipykernel`;
scripts/python-ci.sh installs them). With MONOCULUS_TOUR_HTML set, the executed notebook
is also exported there as HTML, which the browser check opens in headless Chromium
(crates/monoculus-cli/tests/browser.rs)."""

import os
import pathlib

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
TOUR = ROOT / "examples" / "python" / "tour.ipynb"


def _jupyter():
    try:
        import nbclient
        import nbconvert
        import nbformat
    except ImportError as e:
        pytest.fail(
            f"the tour notebook needs a Jupyter kernel and client ({e.name} is missing): "
            "pip install nbclient nbconvert ipykernel"
        )
    return nbclient, nbconvert, nbformat


def test_the_tour_runs_and_shows_its_figure_and_replays():
    nbclient, nbconvert, nbformat = _jupyter()
    nb = nbformat.read(TOUR, as_version=4)
    # Outputs are never committed: what is checked here is what this run made.
    assert all(not c.get("outputs") for c in nb.cells if c.cell_type == "code")
    client = nbclient.NotebookClient(
        nb,
        timeout=600,
        kernel_name="python3",
        resources={"metadata": {"path": str(TOUR.parent)}},
    )
    client.execute()  # raises CellExecutionError on the first cell that fails
    outputs = [o for c in nb.cells if c.cell_type == "code" for o in c.outputs]
    assert not [o for o in outputs if o.output_type == "error"]
    html = [o["data"]["text/html"] for o in outputs if "text/html" in o.get("data", {})]
    replays = [h for h in html if '<iframe class="monoculus-replay"' in h]
    # The stepped simulation's replay and the hunt's counterexample.
    assert len(replays) == 2, [h[:80] for h in html]
    assert any(h.startswith("<p><b>hunt for hull_grows: found") for h in replays)
    assert any("image/png" in o.get("data", {}) for o in outputs), "the figure is shown"
    target = os.environ.get("MONOCULUS_TOUR_HTML")
    if target:
        body, _ = nbconvert.HTMLExporter().from_notebook_node(nb)
        pathlib.Path(target).parent.mkdir(parents=True, exist_ok=True)
        pathlib.Path(target).write_text(body, encoding="utf-8")
