"""Replays shown where the user works: inline in Jupyter, as a page, as a GIF."""

from __future__ import annotations

import html
import os
from typing import Any, Optional, Tuple, Union

import numpy as np

_Path = Union[str, "os.PathLike[str]"]

# The height of the inline frame: the page fits its canvas to the frame (at most 800
# pixels high, the panel beside it).
_FRAME_HEIGHT = 720


class Replay:
    """One recorded run: what ``monoculus replay`` writes, as a Python object.

    In Jupyter the replay page shows inline, in a frame of its own (``srcdoc``, scripts
    only), so that two replays in one notebook never share a script or a style. The page
    is self-contained: it loads nothing, and works in an exported notebook too.

    - :attr:`html`: the page; :meth:`save` writes it, :meth:`gif` the animation.
    - :attr:`verdict` (``converged``, ``stuck``, ``not converged``) and :attr:`outcome`
      (one line, as the page's badge says).
    - :meth:`positions`: the drawn robots in a frame, as the page draws them.
    """

    def __init__(self, native: Any) -> None:
        self._native = native

    @property
    def html(self) -> str:
        """The self-contained replay page."""
        text: str = self._native.html()
        return text

    @property
    def title(self) -> str:
        """Experiment, cell and seed."""
        return str(self._native.title)

    @property
    def subtitle(self) -> str:
        """Algorithm, scheduler, robots."""
        return str(self._native.subtitle)

    @property
    def verdict(self) -> str:
        """``"converged"``, ``"stuck"`` or ``"not converged"`` (a stepped simulation:
        what a run ending where it is now would get)."""
        return str(self._native.verdict)

    @property
    def outcome(self) -> str:
        """How the run ended (or where a stepped one is), one line."""
        return str(self._native.outcome)

    @property
    def frames(self) -> int:
        """Frames kept (a round or event tick each, thinned beyond ``max_mb``)."""
        return int(self._native.frames)

    def positions(self, frame: int = -1) -> np.ndarray:
        """The drawn robots' positions in ``frame`` (default: the last), an
        ``(m, dim)`` array of the single-precision coordinates the page draws."""
        return np.asarray(self._native.frame_positions(frame))

    def save(self, path: _Path) -> str:
        """Writes the page to ``path`` (open it in any browser); returns the path."""
        target = os.fspath(path)
        with open(target, "w", encoding="utf-8") as f:
            f.write(self.html)
        return target

    def gif(self, path: _Path, size: Tuple[int, int] = (480, 480)) -> str:
        """Writes the animation to ``path`` as a GIF of ``size`` pixels (at most 240
        frames, about 8 seconds; the x-y projection in space); returns the path."""
        target = os.fspath(path)
        self._native.gif(target, int(size[0]), int(size[1]))
        return target

    def _repr_html_(self) -> str:
        page = html.escape(self.html, quote=True)
        label = html.escape(f"replay: {self.title}", quote=True)
        return (
            f'<iframe class="monoculus-replay" title="{label}" srcdoc="{page}" '
            f'sandbox="allow-scripts" style="width: 100%; height: {_FRAME_HEIGHT}px; '
            'border: 1px solid #d1d5db; border-radius: 4px"></iframe>'
        )

    def __repr__(self) -> str:
        return f"<monoculus.Replay {self.title!r}: {self.outcome}>"


class HuntResult(dict):  # type: ignore[type-arg]
    """What :func:`monoculus.hunt` returns: ``summary.json`` as a dict (with
    ``positions`` and ``out``), and the counterexample's :class:`Replay` as
    :attr:`replay` (``None`` if no run completed). In Jupyter it shows a line of the
    summary and the replay."""

    def __init__(self, summary: dict[str, Any], replay: Optional[Replay]) -> None:
        super().__init__(summary)
        self.replay = replay

    def _repr_html_(self) -> str:
        found = "found" if self.get("found") else "not found"
        line = html.escape(
            f"hunt for {self.get('property')}: {found}"
            f"{' and shrunk' if self.get('shrunk') else ''}; "
            f"n = {self.get('n')}, {self.get('evaluations')} runs evaluated "
            f"in {float(self.get('seconds') or 0):.1f} s"
        )
        shown = self.replay._repr_html_() if self.replay is not None else ""
        return f"<p><b>{line}</b></p>{shown}"
