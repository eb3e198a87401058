"""The installed package is ready to publish: its metadata (readme, licenses, URLs,
classifiers, keywords, the plot extra) and its typed modules."""

from importlib import metadata

import monoculus


def test_the_metadata_is_complete():
    md = metadata.metadata("monoculus")
    assert md["Name"] == "monoculus" and md["Version"] == monoculus.__version__
    assert md["Requires-Python"] == ">=3.11"
    assert md["License"] == "MIT OR Apache-2.0"
    assert sorted(md.get_all("License-File")) == ["LICENSE-APACHE", "LICENSE-MIT"]
    assert "pip install monoculus" in md.get_payload()  # the readme, as the long description
    urls = dict(u.split(", ", 1) for u in md.get_all("Project-URL"))
    assert {"Homepage", "Repository", "Documentation", "Changelog"} <= set(urls)
    classifiers = md.get_all("Classifier")
    assert "Intended Audience :: Science/Research" in classifiers
    assert "Framework :: Jupyter" in classifiers
    assert "swarm robotics" in md["Keywords"]
    assert md.get_all("Provides-Extra") == ["plot"]
    assert any(r.startswith("matplotlib") and "extra == 'plot'" in r for r in md.get_all("Requires-Dist"))


def test_the_license_files_are_installed():
    files = {str(f) for f in metadata.files("monoculus")}
    assert any(f.endswith("licenses/LICENSE-MIT") for f in files)
    assert any(f.endswith("licenses/LICENSE-APACHE") for f in files)
    assert any(f.endswith("monoculus/py.typed") for f in files)
