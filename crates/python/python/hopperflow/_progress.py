"""Progress of runs and studies: what a progress callable receives, and the built-in bar.

``run`` and ``study`` take the same kind of ``progress`` argument: ``True`` (the built-in
bar), ``False`` (nothing), or a callable that is called with one ``Progress`` each time
there is news: a ``RunProgress`` a few times a second during a run, a ``StudyProgress``
when a study starts and as its cases end. A callable written for ``Progress`` takes
either. An exception it raises stops the run or the study as Ctrl-C does (with a
checkpoint) and propagates.
"""

from __future__ import annotations

import html
import sys
from dataclasses import dataclass
from typing import Any, Callable, Optional, TypeVar, Union


@dataclass(frozen=True)
class Progress:
    """Where a run or a study stands."""

    #: How far along, 0 to 1: for a run, the share of the case's particles inserted
    #: (fill) or discharged (discharge) in its current phase; for a study, the share of
    #: its cases that have ended.
    fraction: float
    #: One line for a person: what the built-in bar shows beside the bar.
    message: str


@dataclass(frozen=True)
class RunProgress(Progress):
    """Where a run stands: its phase, simulated time, particles and speed."""

    #: The phase of the protocol ("fill", "settle", "discharge" or "done").
    phase: str
    #: Simulated time [s].
    time: float
    #: Particles in the simulation.
    particles: int
    #: Particle steps per second of wall-clock time since the previous report.
    particle_steps_per_second: float


@dataclass(frozen=True)
class StudyProgress(Progress):
    """Where a study stands: how many of its cases have ended."""

    #: Cases ended (finished, clogged or failed), those reused from an earlier call included.
    done: int
    #: Cases of the study.
    total: int


P = TypeVar("P", bound=Progress)

#: The ``progress`` argument of ``run`` and ``study``: True, False or a callable taking
#: the progress (its return value is ignored).
ProgressArg = Union[bool, Callable[[P], object]]


class _Bar:
    """The built-in progress display: an HTML bar updated in place in Jupyter, a line on a
    terminal's stderr, nothing elsewhere (logs of scripts stay clean)."""

    def __init__(self, title: str) -> None:
        self.title = title
        self.handle: Any = None
        self.terminal = False
        try:
            from IPython import get_ipython  # noqa: PLC0415 (optional)

            shell = get_ipython()
            notebook = shell is not None and shell.__class__.__name__ == "ZMQInteractiveShell"
        except ImportError:
            notebook = False
        if notebook:
            from IPython.display import HTML, display  # noqa: PLC0415

            self._html = HTML
            self.handle = display(HTML(self._bar(0.0, "starting")), display_id=True)
        else:
            self.terminal = sys.stderr.isatty()

    def _bar(self, fraction: float, text: str) -> str:
        pct = max(0.0, min(1.0, fraction)) * 100
        return (
            f"<div><b>{html.escape(self.title)}</b> "
            f"<progress value='{pct:.1f}' max='100' style='width:40%'></progress> "
            f"{pct:.0f}% <span style='font-family:monospace'>{html.escape(text)}</span></div>"
        )

    def __call__(self, progress: Progress) -> None:
        if self.handle is not None:
            self.handle.update(self._html(self._bar(progress.fraction, progress.message)))
        elif self.terminal:
            filled = int(30 * max(0.0, min(1.0, progress.fraction)))
            sys.stderr.write(f"\r{self.title} [{'=' * filled}{' ' * (30 - filled)}] {progress.message}\033[K")
            sys.stderr.flush()

    def close(self) -> None:
        if self.terminal:
            sys.stderr.write("\n")
            sys.stderr.flush()


def _receiver(progress: ProgressArg[P], title: str) -> "tuple[Optional[Callable[[P], object]], Optional[_Bar]]":
    """The callable that receives the progress, and the built-in bar to close afterwards
    (None when ``progress`` is not True)."""
    if progress is True:
        bar = _Bar(title)
        return bar, bar
    if progress is False:
        return None, None
    if not callable(progress):
        raise TypeError(f"progress: expected True, False or a callable, not {type(progress).__name__}")
    return progress, None
