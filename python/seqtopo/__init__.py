"""seqtopo: topological mapping and localization with the algorithms of DNA sequence alignment.

The Python face of the C++ library (the same code the ``seqtopo`` command runs)::

    import numpy as np
    import seqtopo

    descriptors = _np.load("descriptors.npy")          # N x D, one row per image
    s = seqtopo.similarity(descriptors).similarity     # N x N, S = 1 - kappa * D (cosine, kappa auto)
    result = seqtopo.build_map(s)                      # alignments -> pruning -> places -> topology
    result.labels, result.loop_closures, result.junctions

Functions: :func:`similarity`, :func:`align`, :func:`build_map`, :func:`build_map_from_images`,
:func:`localize`, :func:`match_strings`. Settings: :class:`MapConfig`, :class:`LocalizeConfig`,
:class:`MatchConfig` (with :class:`EditCosts`, :func:`preset_costs`), :class:`AlignConfig`,
:class:`PruningConfig`, :class:`TopologyConfig`, :class:`KappaRule`: the C++ config structs themselves,
so their defaults are the library's. Indices are 0-based, ranges half-open ``[begin, end)``.

Arrays: inputs are read as float32 in C order. :func:`align` reads a float32 C-contiguous array in
place (no copy); other dtypes or layouts are converted once. :func:`build_map`, :func:`localize` and
:func:`similarity` copy their input once into a matrix the library owns. Result arrays are handed over
from the library without a copy and own their memory.

Errors: misuse raises ``ValueError`` with the library's message; a problem with a file (or another
user-given input named by the library) raises :class:`InputError` (a ``ValueError``) whose text is the
command line's ``<file or option>: <message>``. Every long computation releases the GIL, so other Python
threads run meanwhile.
"""

from __future__ import annotations

# Private names: the module's namespace holds only what __all__ lists (and the submodules).
import dataclasses as _dataclasses
import os as _os
import tempfile as _tempfile
import typing as _typing

import numpy as _np

from . import _core
from ._core import (
    AlignConfig,
    EditCosts,
    InputError,
    KappaRule,
    LocalizeConfig,
    MapConfig,
    MatchConfig,
    OnlineMapConfig,
    OnlineMapper,
    PruningConfig,
    TopologyConfig,
    preset_costs,
    preset_names,
)

__version__ = _core.__version__
InputError.__module__ = __name__
InputError.__doc__ = (
    "A problem with a file or other input the user gave (a ValueError). str() is the command line's\n"
    "'<subject>: <message>'; .subject names the file or option and .message says what is wrong."
)

__all__ = [
    "AlignConfig",
    "Alignment",
    "EditCosts",
    "InputError",
    "KappaRule",
    "LocalizeConfig",
    "LocalizeResult",
    "LocalizeRun",
    "MapConfig",
    "MapResult",
    "MapRun",
    "MatchConfig",
    "OnlineMapConfig",
    "OnlineMapper",
    "ProgressEvent",
    "PruningConfig",
    "SimilarityResult",
    "StringMatches",
    "TopologyConfig",
    "TqdmProgress",
    "align",
    "build_map",
    "build_map_from_images",
    "localize",
    "localize_sequences",
    "map_preset",
    "map_sequence",
    "match_strings",
    "preset_costs",
    "preset_names",
    "similarity",
    "write_report",
]



@_dataclasses.dataclass(frozen=True, eq=False, repr=False)
class Alignment:
    """One local alignment, as in ``alignments.json``.

    ``score``: the (capped) cumulative score at its last cell; ``direction``: ``"forward"`` (i and j grow
    together) or ``"reverse"`` (j shrinks while i grows); ``a_begin, a_end, b_begin, b_end``: half-open
    ranges spanning the aligned pairs; ``pairs``: the aligned pairs ``(i, j)`` as an ``(n, 2)`` int64
    array in increasing i (elements skipped by a gap are in the ranges but not in the pairs).
    """

    score: float
    direction: str
    a_begin: int
    a_end: int
    b_begin: int
    b_end: int
    pairs: _np.ndarray

    def to_dict(self) -> dict:
        """The ``alignments.json`` record (without ``kept``)."""
        return {
            "score": self.score,
            "direction": self.direction,
            "a_begin": self.a_begin,
            "a_end": self.a_end,
            "b_begin": self.b_begin,
            "b_end": self.b_end,
            "pairs": self.pairs.tolist(),
        }

    def __repr__(self) -> str:
        return (f"Alignment({self.direction}, score {self.score:.4g}, a {self.a_begin}..{self.a_end - 1}, "
                f"b {self.b_begin}..{self.b_end - 1}, {len(self.pairs)} pairs)")

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, Alignment):
            return NotImplemented
        return (self.score, self.direction, self.a_begin, self.a_end, self.b_begin, self.b_end) == (
            other.score, other.direction, other.a_begin, other.a_end, other.b_begin, other.b_end
        ) and _np.array_equal(self.pairs, other.pairs)


def _alignments(raw) -> list[Alignment]:
    return [Alignment(*fields) for fields in raw]


@_dataclasses.dataclass(frozen=True, repr=False)
class SimilarityResult:
    """The similarity matrix and how it was made.

    ``similarity``: float32 N x N (or N x M with ``against``: rows = the first input);
    ``kappa``: the kappa of ``S = 1 - kappa * D`` (NaN when the input already was a similarity matrix);
    ``kappa_auto``/``kappa_fraction``: chosen automatically, giving this fraction of candidate pairs
    ``S > 0``; ``metric``: ``"chi2"``, ``"l1"``, ``"cosine"`` or ``"sad"`` (None for a similarity input);
    ``frame_names``/``column_names``: file names, ``"frame 17"`` or ``"row 17"``.
    """

    similarity: _np.ndarray
    kappa: float
    kappa_auto: bool
    kappa_fraction: float
    metric: str | None
    frame_names: list[str]
    column_names: list[str]

    def __repr__(self) -> str:
        r, c = self.similarity.shape
        how = "a similarity input" if self.metric is None else f"{self.metric}, kappa {self.kappa:.4g}"
        return f"SimilarityResult({r} x {c}, {how}{' (auto)' if self.kappa_auto else ''})"


def _input_error(subject: str, message: str) -> InputError:
    error = InputError(f"{subject}: {message}")
    error.subject = subject
    error.message = message
    return error


def _whole(name: str, value, minimum: int = 0) -> int:
    """A count argument as the native call takes it, or the ValueError the errors section documents (pybind11
    would raise TypeError for -1, 2.5 or "3")."""
    if not isinstance(value, int) or isinstance(value, bool) or value < minimum or value > 2**63 - 1:
        raise ValueError(f"{name}: must be an integer >= {minimum}, got {value!r}")
    return value


def _is_path(x) -> bool:
    return isinstance(x, (str, _os.PathLike))


def similarity(
    descriptors,
    against=None,
    *,
    metric: str | None = None,
    kappa: float | None = None,
    threads: int = 0,
    kappa_rule: KappaRule | None = None,
    descriptor: str = "joint-histogram",
    input_kind: str = "auto",
    every: int = 1,
) -> SimilarityResult:
    """Similarity matrix ``S = 1 - kappa * D`` of a sequence, as ``seqtopo similarity`` computes it.

    ``descriptors``: an N x D array, one row per image (what ``seqtopo similarity descriptors.npy``
    reads), or a path to an image folder, a video, a ``descriptors.npy`` or a ``similarity.npy``.
    ``against``: a second sequence of the same kind for an N x M matrix (rows = ``descriptors``).
    ``metric``: ``"chi2"``, ``"l1"``, ``"cosine"`` or ``"sad"``; default cosine for descriptor rows (chi2
    for joint histograms, sad for patches). ``kappa``: a number > 0, or None to choose it from the
    sequence's own distances (``kappa_rule``). ``threads``: 0 = every core; the matrix does not depend
    on it. ``descriptor`` (``"joint-histogram"``, ``"patch"``, ...), ``input_kind``, ``every``: for a
    path, as the command line's options.

    Raises ValueError (unknown metric, chi2 on negative values, non-finite or empty input,
    ``kappa <= 0``), :class:`InputError` for an unreadable path, MemoryError when the matrix cannot fit.
    """
    rule = kappa_rule if kappa_rule is not None else KappaRule()
    threads, every = _whole("threads", threads), _whole("every", every, 1)
    if _is_path(descriptors):
        if against is not None and not _is_path(against):
            raise ValueError("against: give a path when the first input is a path")
        raw = _core.similarity_of_path(
            _os.fspath(descriptors), None if against is None else _os.fspath(against), descriptor, metric, kappa,
            input_kind, every, threads, rule,
        )
    else:
        raw = _core.similarity_of_descriptors(descriptors, against, metric, kappa, threads, rule)
    return SimilarityResult(**raw)


def align(
    scores,
    *,
    gap: float | None = None,
    gap_a: float | None = None,
    gap_b: float | None = None,
    cap: float | None = AlignConfig().cap,
    threshold: float = AlignConfig().threshold,
    reverse: bool = True,
    self: bool = AlignConfig().self,
    min_separation: int = AlignConfig().min_separation,
    max_alignments: int | None = AlignConfig().max_alignments,
    threads: int = 2,
) -> list[Alignment]:
    """All non-intersecting local alignments of a score matrix, best first (``seqtopo align --scores``).

    ``scores``: rows = elements of A, columns = elements of B, higher = better match; a float32
    C-contiguous array is read in place. ``gap``: penalty per skipped element of either sequence
    (``gap_a``/``gap_b`` set them apart; default :class:`AlignConfig`'s). ``cap``: upper bound on the
    cumulative score (None: classical Smith-Waterman). ``threshold``: minimum score reported.
    ``reverse``: also search alignments with B read backwards (a path revisited in the opposite
    direction); note that ``seqtopo align`` searches them only with ``--reverse``. ``self``: A and B are
    one sequence (square matrix): only pairs with ``i - j >= min_separation`` are searched.
    ``max_alignments``: stop after this many (None: all). ``threads``: forward and reverse passes in
    parallel when > 1; the result does not depend on it.

    Returns a list of :class:`Alignment`; an empty list when nothing scores above the threshold.
    """
    threads = _whole("threads", threads)
    default = AlignConfig()
    config = AlignConfig(
        gap_a=gap_a if gap_a is not None else (gap if gap is not None else default.gap_a),
        gap_b=gap_b if gap_b is not None else (gap if gap is not None else default.gap_b),
        cap=cap,
        threshold=threshold,
        max_alignments=max_alignments,
        self=self,
        min_separation=min_separation,
    )
    return _alignments(_core.align(scores, config, reverse, threads))


@_dataclasses.dataclass(frozen=True, eq=False, repr=False)
class MapResult:
    """A topological map and the alignments it came from (``map.json``, ``loop_closures.csv``).

    ``labels``: int32 place id per image; ``places``: per place id, the int64 array of its images;
    ``edges``: ``(E, 2)`` place pairs ``(p, q)``, ``p < q``, of consecutive images; ``junctions``: place
    ids where the path branches or merges; ``segments``: chains of place ids between junctions;
    ``alignments``: every :class:`Alignment` found, best first; ``kept``: per alignment, whether it
    survived pruning; ``retained_count``: its surviving pairs; ``loop_closures``: ``(K, 2)`` retained
    image pairs ``(i, j)``, ``i > j`` (the rows of ``loop_closures.csv``), with
    ``loop_closure_scores`` (the score of their alignment), ``loop_closure_confidences`` (the probability
    that the pair is a revisit, INTERFACE.md) and ``loop_closure_alignments`` (its index);
    ``scores``: the matrix that was aligned (S or its contrast-enhanced form); ``similarities``: for
    :func:`build_map_from_images`, the similarity matrix of each descriptor, else empty.
    """

    labels: _np.ndarray
    places: list[_np.ndarray]
    edges: _np.ndarray
    junctions: _np.ndarray
    segments: list[_np.ndarray]
    alignments: list[Alignment]
    kept: _np.ndarray
    retained_count: _np.ndarray
    loop_closures: _np.ndarray
    loop_closure_scores: _np.ndarray
    loop_closure_confidences: _np.ndarray
    loop_closure_alignments: _np.ndarray
    scores: _np.ndarray
    seconds_align: float
    seconds_prune_label: float
    similarities: list[SimilarityResult] = _dataclasses.field(default_factory=list)

    @property
    def images(self) -> int:
        """Number of images in the sequence."""
        return len(self.labels)

    def __repr__(self) -> str:
        kept = int(_np.count_nonzero(self.kept))
        return (f"MapResult({self.images} images, {len(self.places)} places, {len(self.junctions)} junctions, "
                f"{len(self.alignments)} alignments ({kept} kept), {len(self.loop_closures)} loop closures)")

    def to_json(self) -> dict:
        """The content of ``map.json`` as ``seqtopo map`` writes it."""
        alignments = []
        for a, kept in zip(self.alignments, self.kept):
            record = a.to_dict()
            record["kept"] = bool(kept)
            alignments.append(record)
        return {
            "images": self.images,
            "labels": self.labels.tolist(),
            "places": [{"id": k, "images": p.tolist()} for k, p in enumerate(self.places)],
            "edges": self.edges.tolist(),
            "junctions": self.junctions.tolist(),
            "segments": [s.tolist() for s in self.segments],
            "alignments": alignments,
        }


def _config(config, cls, overrides):
    """A copy of `config` (default: cls()) with the keyword overrides applied."""
    if config is None:
        config = cls()
    elif not isinstance(config, cls):
        raise TypeError(f"config must be a {cls.__name__}, got {type(config).__name__}")
    if not overrides:
        return config
    fields = {name: getattr(config, name) for name in _fields(cls)}
    unknown = set(overrides) - set(fields)
    if unknown:
        raise TypeError(f"{cls.__name__} has no field {', '.join(sorted(unknown))}")
    fields.update(overrides)
    try:
        return cls(**fields)
    except TypeError:
        # pybind11 lists every constructor argument; say which override it could not take, and why.
        for name, value in overrides.items():
            try:
                setattr(cls(), name, value)
            except TypeError:
                current = getattr(cls(), name)
                if isinstance(current, bool):
                    why = "must be True or False"
                elif isinstance(current, int):
                    why = "must be an integer >= 0"
                elif current is None or isinstance(current, float):
                    why = "must be a number"
                else:
                    why = f"must be a {type(current).__name__}"
                raise ValueError(f"{name}: {why}, got {value!r}") from None
        raise


def _fields(cls) -> list[str]:
    return [name for name in dir(cls) if not name.startswith("_") and isinstance(getattr(cls, name), property)]


def _map_result(raw: dict, similarities=()) -> MapResult:
    raw["alignments"] = _alignments(raw["alignments"])
    return MapResult(similarities=list(similarities), **raw)


def build_map(similarity, config: MapConfig | None = None, **overrides) -> MapResult:
    """The mapping paper end to end from a similarity matrix (what ``seqtopo map`` does after step 1).

    ``similarity``: an N x N matrix (higher = more similar), or a list of them for the same sequence
    (several descriptors or sensors, fused: each contrast-enhanced on its own, then averaged), or a
    path, which goes to :func:`build_map_from_images`. ``config``: a :class:`MapConfig`; keyword
    arguments override its fields, e.g. ``build_map(s, gap=2.0, cap=None)``.

    Forward and reverse self alignments with the score cap, per-column pruning, transitive labels,
    topology. Raises ValueError for an empty, non-square or non-finite matrix or a bad setting.
    """
    if _is_path(similarity):
        return build_map_from_images(similarity, config, **overrides)
    config = _config(config, MapConfig, overrides)
    if isinstance(similarity, (list, tuple)) and similarity and all(_np.ndim(s) == 2 for s in similarity):
        matrices = list(similarity)
    else:
        matrices = [similarity]
    for m in matrices:
        _require_square(m)
    return _map_result(_core.build_map(matrices, config))


def _require_square(matrix) -> None:
    """A map needs N x N similarities; an N x D array is descriptors, and the error says what to call."""
    shape = _np.shape(matrix)
    if len(shape) == 2 and shape[0] != shape[1] and shape[0] > 0 and shape[1] > 0:
        raise ValueError(
            f"similarity: a map needs a square N x N similarity matrix (image x image), got {shape[0]} x {shape[1]}. "
            f"If these are descriptors (one row per image), compute the similarity first: "
            f"seqtopo.build_map(seqtopo.similarity(descriptors).similarity), or map them in one call: "
            f"seqtopo.map_sequence(descriptors)")


def build_map_from_images(
    path: str | _os.PathLike[str],
    config: MapConfig | None = None,
    *,
    descriptors: list[str] | None = None,
    metric: str | None = None,
    kappa: float | None = None,
    input_kind: str = "auto",
    every: int = 1,
    threads: int = 0,
    preset: str = "default",
    **overrides,
) -> MapResult:
    """``seqtopo map INPUT`` without the files: an image folder, video, ``descriptors.npy`` or
    ``similarity.npy`` in, a :class:`MapResult` out (``map_sequence(...).map``).

    ``descriptors``: one similarity matrix per descriptor (the names ``seqtopo map --descriptor`` takes:
    ``"joint-histogram"``, ``"patch"``, ...), fused as in :func:`build_map`; default: the preset's. A ``.npy``
    input is one matrix whatever is asked for. ``metric``, ``kappa``, ``input_kind``, ``every``, ``threads``,
    ``preset``: as the command's options. Keyword arguments override fields of ``config`` (default: the
    preset's). The similarity matrices are in ``result.similarities``.
    """
    return map_sequence(path, config, descriptors=descriptors, metric=metric, kappa=kappa, input_kind=input_kind,
                        every=every, threads=threads, preset=preset, **overrides).map


def map_preset(name: str = "default") -> dict:
    """The settings ``seqtopo map --preset NAME`` starts from: ``{"config": MapConfig, "descriptors": [...],
    "metric": str or None}`` (``"default"`` or ``"paper"``, the mapping paper's own pipeline)."""
    return _core.map_preset(name)


class MapRun:
    """Everything one :func:`map_sequence` computed: the map (``.map``, a :class:`MapResult`), the accuracy
    against the ground truth (``.metrics``, and the SeqSLAM-style ``.baseline`` on the same matrices),
    ``.topology`` and ``.trajectory_errors`` (with places or poses), ``.timings`` (stage, seconds: consecutive
    parts of the run), ``.engine`` (the engine that ran: ``"exact"``, ``"fast"``, ``"streaming"`` or ``"sparse"``),
    ``.sessions`` (``{"input", "begin", "end"}`` of each session, the inputs' and those begun at a break found
    inside one, which also has ``"break": {"gap", "median_interval"}``). :func:`write_report` writes it as
    ``seqtopo map`` does."""

    def __init__(self, raw):
        self._raw = raw
        self.map = _map_result(raw.result, [SimilarityResult(**r) for r in raw.similarities])
        self.metrics = raw.metrics
        self.baseline = raw.baseline
        self.topology = raw.topology
        self.trajectory_errors = raw.trajectory_errors
        self.timings = list(raw.timings)
        self.descriptor_names = list(raw.descriptor_names)
        self.input = raw.input
        self.preset = raw.preset
        self.engine = raw.engine
        self.sessions = list(raw.sessions)

    def __repr__(self) -> str:
        m = self.map
        name = _os.path.basename(_os.path.normpath(self.input)) if self.input != "memory" else "memory"
        text = (f"MapRun({name}: {m.images} images, {len(m.places)} places, {len(m.junctions)} junctions, "
                f"{len(m.loop_closures)} loop closures")
        if self.metrics:
            text += (f"; F1 {self.metrics['f1']:.3f} (precision {self.metrics['precision']:.3f}, "
                     f"recall {self.metrics['recall']:.3f})")
        if self.baseline:
            text += f", baseline F1 {self.baseline['f1']:.3f}"
        if self.topology:
            text += f"; ARI {self.topology['adjusted_rand_index']:.3f}"
        if self.trajectory_errors:
            text += f"; ATE pose graph {self.trajectory_errors['pose_graph']:.2f} m"
        return text + f"; {sum(t for _, t in self.timings):.2f} s)"


def _arrays(x) -> bool:
    return isinstance(x, _np.ndarray) or (isinstance(x, (list, tuple)) and x and all(
        isinstance(m, _np.ndarray) for m in x))


def _refuse_path_options(**given) -> None:
    """Options that read or compute from files, given with arrays in memory: one error naming the first."""
    defaults = {"engine": None, "streaming": False, "sparse": False, "neighbours": None, "diagonal_reach": None,
                "descriptors": None, "input_kind": "auto", "metric": None, "kappa": None}
    for name, value in given.items():
        if value is not None and value != defaults[name]:
            what = ("compares descriptors; a similarity matrix is mapped as it is" if name in ("metric", "kappa")
                    else "applies to a path input (an image folder, video or .npy file); save the array with "
                         "numpy.save and give its path")
            raise ValueError(f"{name}: {what}")


def _thinned(name: str, value, recorded: int, every: int, recording_only: bool = False, square: bool = False):
    """A per-frame array for descriptors thinned by `every` from `recorded` rows: the rows of the images kept as
    they are, or the recording's rows thinned alike (as the command thins a ground truth file; an odometry lists
    every frame of the recording). A same-place matrix is thinned on both axes."""
    if value is None:
        return None
    value = _np.asarray(value)
    square = square and value.ndim == 2 and value.shape[0] == value.shape[1]
    kept = (recorded + every - 1) // every
    rows = value.shape[0] if value.ndim > 0 else 0
    if rows == recorded:
        return value[::every, ::every] if square else value[::every]
    if rows == kept and not recording_only:
        return value
    fits = f"the {recorded} frames of the recording" if recording_only else \
        f"the {kept} images kept, or the {recorded} frames of the recording every={every} kept them from"
    raise ValueError(f"{name}: has {rows} rows, the sequence has {kept} images after every={every} (give {fits})")


def _same_place_from_poses(poses, radius: float):
    """N x N: images closer than radius [m] (the command line's poses.csv with --gt-radius)."""
    xy = _np.asarray(poses, dtype=_np.float64)[:, :2]
    d = _np.sqrt(((xy[:, None, :] - xy[None, :, :]) ** 2).sum(axis=2))
    return d <= radius


@_dataclasses.dataclass(frozen=True)
class ProgressEvent:
    """One event of a long job, for ``map_sequence(..., progress=callback)``: the job announces its stages once
    (``kind == "plan"``), then sends per stage one ``"begin"``, any number of ``"advance"`` (``done`` units of
    ``total``, what a unit is in ``unit``, ``total`` 0 when the stage cannot count) and one ``"end"`` (its wall
    time in ``seconds``). Stages are numbered ``stage`` of ``stages``, from 1 (0 for the plan)."""

    kind: str
    stage: int
    stages: int
    name: str
    done: int
    total: int
    unit: str
    seconds: float


def _progress_callback(progress: _typing.Callable[[ProgressEvent], object] | None) -> _typing.Callable[..., object] | None:
    if progress is None:
        return None
    if not callable(progress):
        raise TypeError(f"progress: must be a callable taking a seqtopo.ProgressEvent, got {type(progress).__name__}")
    return lambda *fields: progress(ProgressEvent(*fields))


class TqdmProgress:
    """``progress=`` for :func:`map_sequence` that draws one tqdm bar per stage (``tqdm.auto``, so a notebook gets
    its widget). Needs tqdm (Debian python3-tqdm, ``pip install tqdm``); without it the constructor raises
    ImportError. Keyword arguments go to each bar (``leave=False``, ``file=...``)."""

    def __init__(self, **tqdm_options: object) -> None:
        try:
            from tqdm.auto import tqdm
        except ImportError as error:
            raise ImportError("seqtopo.TqdmProgress needs tqdm (Debian: python3-tqdm; pip install tqdm)") from error
        self._tqdm = tqdm
        self._options = tqdm_options
        self._bar = None

    def __call__(self, event: ProgressEvent) -> None:
        if event.kind == "begin":
            self.close()
            self._bar = self._tqdm(desc=f"[{event.stage}/{event.stages}] {event.name}", **self._options)
        elif event.kind == "advance" and self._bar is not None:
            if event.total and self._bar.total != event.total:
                self._bar.total = event.total
                self._bar.unit = " " + event.unit
            self._bar.update(event.done - self._bar.n)
        elif event.kind == "end":
            self.close()

    def close(self) -> None:
        if self._bar is not None:
            self._bar.close()
            self._bar = None


def map_sequence(
    path,
    config: MapConfig | None = None,
    *,
    preset: str = "default",
    descriptors: list[str] | None = None,
    metric: str | None = None,
    kappa: float | None = None,
    input_kind: str = "auto",
    every: int = 1,
    threads: int = 0,
    odometry=None,
    ground_truth=None,
    gt_radius: float | None = None,
    gt_places=None,
    gt_junctions=None,
    gt_poses=None,
    engine: str = "automatic",
    streaming: bool = False,
    sparse: bool = False,
    neighbours: int | None = None,
    diagonal_reach: int | None = None,
    names: list[str] | None = None,
    progress: _typing.Callable[[ProgressEvent], object] | None = None,
    **overrides,
) -> MapRun:
    """``seqtopo map`` as one call, on the same library pipeline. Returns a :class:`MapRun`;
    :func:`write_report` writes its files.

    ``path``: an image folder, video, ``descriptors.npy`` or ``similarity.npy`` (as the command's INPUT), a list of
    such paths (sessions, as ``seqtopo map S1 S2 ...``: no transition from one's last frame to the next one's
    first; ``odometry`` then one file per session or none), or arrays
    in memory: one N x N similarity matrix, a list of them (fused), or an N x D array of descriptors (compared by
    :func:`similarity` first). The ``preset``'s settings apply; ``config`` and keyword overrides replace its
    :class:`MapConfig`.

    Odometry and ground truth, as files for a path input (the command's ``--odometry``, ``--ground-truth`` with
    ``--gt-radius``, ``--gt-places``, ``--gt-poses``) or as arrays for an array input: ``odometry`` N x 3
    (x, y, theta [m, m, rad], cumulative), ``ground_truth`` an N x N same-place matrix or N x 2 positions with
    ``gt_radius`` [m], ``gt_places`` the true place per image (``gt_junctions``: the true junction places),
    ``gt_poses`` N x 3 true poses. ``names``: one per matrix, for the report. ``engine`` is the command's
    ``--engine``: ``"automatic"`` (chosen by the memory the run needs, as the command chooses it), ``"exact"``,
    ``"fast"``, ``"streaming"`` or ``"sparse"`` (with ``neighbours`` candidates per frame, default 10, and
    ``diagonal_reach``); ``streaming=True`` and ``sparse=True`` are the command's ``--streaming`` and ``--sparse``;
    all for a path input. ``every``: as the command's
    ``--every``; with descriptors in memory it keeps rows 0, k, 2k, ..., thins ``odometry`` (every frame's) alike,
    and a ground truth of every frame too (one of the rows kept is used as it is). Options that only apply to a
    path input, or ``metric``/``kappa`` with similarity matrices, are refused rather than ignored.

    ``progress``: a callable that gets a :class:`ProgressEvent` as each stage begins, advances and ends (from the
    calling thread or the job's, one at a time); :class:`TqdmProgress` draws them as tqdm bars. An exception it
    raises stops the events and is raised when the job returns."""
    callback = _progress_callback(progress)
    if config is None:
        config = map_preset(preset)["config"]
    config = _config(config, MapConfig, overrides)
    every, threads = _whole("every", every, 1), _whole("threads", threads)
    if _arrays(path):
        matrices = list(path) if isinstance(path, (list, tuple)) else [path]
        descriptor_rows = len(matrices) == 1 and matrices[0].ndim == 2 and matrices[0].shape[0] != matrices[0].shape[1]
        _refuse_path_options(engine=None if engine == "automatic" else engine, streaming=streaming, sparse=sparse,
                             neighbours=neighbours, diagonal_reach=diagonal_reach, descriptors=descriptors,
                             input_kind=input_kind,
                             metric=None if descriptor_rows else metric, kappa=None if descriptor_rows else kappa)
        for name, value in (("odometry", odometry), ("ground_truth", ground_truth), ("gt_places", gt_places),
                            ("gt_poses", gt_poses)):
            if value is not None and _is_path(value):
                raise ValueError(f"{name}: give an array with arrays in memory (a file goes with a path input)")
        if not isinstance(every, int) or isinstance(every, bool) or every < 1:
            raise ValueError(f"every: must be an integer >= 1, got {every!r}")
        if every > 1:
            if not descriptor_rows:
                raise ValueError("every: a similarity matrix is not thinned (as the command refuses --every with "
                                 "similarity.npy); slice it: matrix[::k, ::k]")
            recorded = matrices[0].shape[0]
            matrices = [matrices[0][::every]]
            odometry = _thinned("odometry", odometry, recorded, every, recording_only=True)
            ground_truth = _thinned("ground_truth", ground_truth, recorded, every, square=True)
            gt_places = _thinned("gt_places", gt_places, recorded, every)
            gt_poses = _thinned("gt_poses", gt_poses, recorded, every)
        if descriptor_rows:
            matrices = [similarity(matrices[0], metric=metric, kappa=kappa, threads=threads).similarity]
            names = names or ["descriptors (cosine)"]
        for m in matrices:
            _require_square(m)
        same_place = None
        if ground_truth is not None:
            truth = _np.asarray(ground_truth)
            if truth.ndim == 2 and truth.shape[1] in (2, 3) and truth.shape[0] != truth.shape[1]:
                if gt_radius is None:
                    raise ValueError("ground_truth: positions (N x 2) need gt_radius [m]")
                if not _np.isfinite(truth).all():
                    raise ValueError("ground_truth: positions must be finite")
                truth = _same_place_from_poses(truth, gt_radius)
            same_place = truth.astype(_np.float32)
        raw = _core.map_similarities(
            matrices, list(names or []), config, None if odometry is None else _np.asarray(odometry, _np.float32),
            same_place, [] if gt_places is None else [int(p) for p in gt_places],
            [] if gt_junctions is None else [int(j) for j in gt_junctions],
            None if gt_poses is None else _np.asarray(gt_poses, _np.float32), callback)
        return MapRun(raw)
    if isinstance(descriptors, str):
        descriptors = descriptors.split(",")
    if descriptors is not None and not descriptors:
        raise ValueError("no descriptor given")
    for name, value in (("odometry", odometry), ("ground_truth", ground_truth), ("gt_places", gt_places),
                        ("gt_poses", gt_poses)):
        files = value if name == "odometry" and isinstance(value, (list, tuple)) else [value]
        if value is not None and not all(_is_path(f) for f in files):
            raise ValueError(f"{name}: give a file with a path input (arrays go with arrays in memory)")
    if gt_junctions is not None:
        raise ValueError("gt_junctions: with a path input they are read from junctions.csv beside gt_places")

    def fs(p):
        return "" if p is None else _os.fspath(p)
    paths = [_os.fspath(p) for p in path] if isinstance(path, (list, tuple)) else [_os.fspath(path)]
    if not paths:
        raise ValueError("path: no input given (an empty list)")
    if odometry is None:
        odometry_files = []
    elif isinstance(odometry, (list, tuple)):
        odometry_files = [_os.fspath(p) for p in odometry]
    else:
        odometry_files = [_os.fspath(odometry)]
    raw = _core.map_sequence(paths, preset, config, list(descriptors or []), metric, kappa, input_kind,
                             every, threads, odometry_files, fs(ground_truth), gt_radius, fs(gt_places), fs(gt_poses),
                             engine, streaming, sparse, neighbours, diagonal_reach, callback)
    return MapRun(raw)


class LocalizeRun:
    """Everything one :func:`localize_sequences` computed: per query frame ``.map`` (the best guess, offline and
    online), ``.score`` (local alignment score; online the table value), ``.confidence`` (the probability the guess
    is right; online from the frames so far) and ``.in_map`` (confidence >= the minimum); ``.alignments``
    (offline); with ground truth ``.metrics`` (recall@1, AUC, ... ranked by confidence), ``.calibration`` (expected
    calibration error) and ``.baselines`` (single frame, SeqSLAM; each on the matrix that suits it best); ``.similarity`` (query x map), ``.timings``;
    online ``.latencies`` (processing per frame, from arrival to answer [s]) and ``.waits``.
    :func:`write_report` writes it as ``seqtopo localize`` does."""

    def __init__(self, raw):
        self._raw = raw
        self.online = raw.online
        self.inputs = raw.inputs
        self.queries, self.maps = raw.queries, raw.maps
        self.map, self.score = raw.map, raw.score
        self.confidence, self.in_map = raw.confidence, raw.in_map
        self.alignments = _alignments(raw.alignments)
        self.metrics, self.baselines, self.calibration = raw.metrics, raw.baselines, raw.calibration
        self.timings = list(raw.timings)
        self.latencies, self.waits = raw.latencies, raw.waits
        self.tolerance = raw.tolerance

    @property
    def similarity(self) -> _np.ndarray:
        """The query x map similarity (a copy)."""
        return self._raw.similarity

    def __repr__(self) -> str:
        found = int(_np.count_nonzero(self.in_map))
        inputs = " in ".join(_os.path.basename(p) for p in self.inputs.split(" in "))
        text = (f"LocalizeRun({inputs}: {self.queries} query frames in {self.maps} map frames, {found} in the "
                f"map, {'online' if self.online else f'{len(self.alignments)} alignments'}")
        if self.metrics:
            text += f"; recall@1 {self.metrics['recall_at_1']:.3f}, AUC {self.metrics['auc']:.3f} (+-{self.tolerance})"
        if self.online and len(self.latencies):
            text += f"; latency median {1e3 * float(_np.median(self.latencies)):.2f} ms"
        return text + ")"


def localize_sequences(
    map,
    query=None,
    config: LocalizeConfig | None = None,
    *,
    descriptor: str | None = None,
    metric: str | None = None,
    kappa: float | None = None,
    input_kind: str = "auto",
    every: int = 1,
    threads: int = 0,
    online: bool = False,
    ground_truth=None,
    tolerance: "int | None" = None,
    **overrides,
) -> "LocalizeRun":
    """``seqtopo localize`` as one call: where in the mapped traverse ``map`` is each frame of ``query``?

    ``map``, ``query``: image folders, videos or ``descriptors.npy`` (the command's ``--map``/``--query``); or
    ``map`` alone a query x map similarity (a ``similarity.npy`` path or an array, rows = query frames).
    ``config``: a :class:`LocalizeConfig`, keyword arguments override its fields. ``online``: frame by frame
    (with ``lag=L``, each frame answered once L later frames have arrived, with their evidence: fixed-lag smoothing).
    ``descriptor``: one name or several comma-separated (fused); ``None``, the map's default (joint histogram and
    patch, panorama for 360-degree images), as the command without ``--descriptor``.
    ``ground_truth``: ``"same-index"`` (query k is map k), a CSV of ``query,map`` pairs, or an array of such
    pairs; the answers are then scored within +-``tolerance`` map frames beside the single-frame and SeqSLAM
    baselines (``None``: as the command, 2 with ``"same-index"``, the frames as listed in a file or an array). The
    answers do not depend on it (``config.tolerance`` sets the confidence's window). Returns a :class:`LocalizeRun`."""
    config = _config(config, LocalizeConfig, overrides)
    every, threads = _whole("every", every, 1), _whole("threads", threads)
    tolerance = None if tolerance is None else _whole("tolerance", tolerance)
    with _tempfile.TemporaryDirectory(prefix="seqtopo-") as scratch:
        written = {}  # files made here from arrays: an error names the argument, not the file
        if isinstance(map, _np.ndarray):
            if query is not None:
                raise ValueError("map: an array is the query x map similarity; give no query with it")
            path = _os.path.join(scratch, "similarity.npy")
            _np.save(path, _np.ascontiguousarray(map, dtype=_np.float32))
            map = path
            written[path] = "map"
        truth = ""
        if ground_truth is not None:
            if isinstance(ground_truth, str) or isinstance(ground_truth, _os.PathLike):
                truth = _os.fspath(ground_truth)
            else:
                pairs = _np.asarray(ground_truth, dtype=_np.int64).reshape(-1, 2)
                truth = _os.path.join(scratch, "truth.csv")
                with open(truth, "w") as f:
                    f.write("query,map\n" + "".join(f"{q},{m}\n" for q, m in pairs))
                written[truth] = "ground_truth"
        try:
            raw = _core.localize_sequences(_os.fspath(map), "" if query is None else _os.fspath(query),
                                           "" if descriptor is None else descriptor,
                                           metric, kappa, input_kind, every, threads, config, online, truth,
                                           tolerance)
        except (ValueError, InputError) as error:
            message = str(error)
            for path, name in written.items():
                message = message.replace(path, name)
            if message == str(error):
                raise
            raise type(error)(message) from None
    return LocalizeRun(raw)


def write_report(run: MapRun | LocalizeRun, folder: str | _os.PathLike[str]) -> None:
    """Writes a :class:`MapRun` as ``seqtopo map --out folder`` does (map.json, figures, report.html), or a
    :class:`LocalizeRun` as ``seqtopo localize --out folder`` does (matches.csv, figures, report.html),
    replacing the folder's previous outputs as a whole."""
    if isinstance(run, MapRun):
        _core.write_map_outputs(run._raw, _os.fspath(folder))
    elif isinstance(run, LocalizeRun):
        _core.write_localize_outputs(run._raw, _os.fspath(folder))
    else:
        raise TypeError(f"write_report takes a MapRun (map_sequence) or a LocalizeRun (localize_sequences), "
                        f"got {type(run).__name__}")


@_dataclasses.dataclass(frozen=True, eq=False, repr=False)
class LocalizeResult:
    """Where each query frame is in the map (``matches.csv`` and more).

    Per query frame (row of the query x map matrix): ``map`` (int64 best guess of the map frame, given for
    every frame), ``confidence`` (float64, the probability that the guess is right: exp(-E) of its alignment
    times the posterior), ``e_value`` (of that alignment; NaN when none or no fit), ``score`` (float32 local
    alignment score), ``covered`` (bool, in the map: confidence >= ``LocalizeConfig.min_confidence``),
    ``direction`` (``"forward"``/``"reverse"``), ``candidates`` (``(Q, LocalizeConfig.candidates)`` int64,
    best first, padded with -1). ``alignments``: every :class:`Alignment` found (a = query, b = map), best
    first, chance ones included (they are the significance statistics' sample).
    """

    map: _np.ndarray
    score: _np.ndarray
    confidence: _np.ndarray
    e_value: _np.ndarray
    covered: _np.ndarray
    direction: _np.ndarray
    candidates: _np.ndarray
    alignments: list[Alignment]

    def __repr__(self) -> str:
        return (f"LocalizeResult({len(self.map)} query frames, {int(_np.count_nonzero(self.covered))} in the map, "
                f"{len(self.alignments)} alignments)")


def localize(similarity, config: LocalizeConfig | None = None, **overrides) -> LocalizeResult:
    """Sequence-based localization of a query traverse in a mapped one (``seqtopo localize``).

    ``similarity``: the query x map matrix (rows = query frames, columns = map frames, higher = more
    similar), e.g. ``seqtopo.similarity(query_descriptors, map_descriptors).similarity``.
    ``config``: a :class:`LocalizeConfig`; keyword arguments override its fields.
    Raises ValueError for an empty or non-finite matrix or a bad setting.
    """
    config = _config(config, LocalizeConfig, overrides)
    raw = _core.localize(similarity, config)
    reverse = raw.pop("reverse")
    return LocalizeResult(
        direction=_np.where(reverse, "reverse", "forward"),
        alignments=_alignments(raw.pop("alignments")),
        **raw,
    )


@_dataclasses.dataclass(frozen=True, eq=False, repr=False)
class StringMatches:
    """The ranked candidates of one query string (rows of ``matches.tsv``).

    ``db_index``: database strings that matched, best first (ties in database order); ``score``: their
    cost (lower is better); ``rank``: 1 = among the best matchings, ties share a rank (1, 1, 3, ...);
    ``rotation``: with ``cyclic``, the best rotation of the database string.
    """

    db_index: _np.ndarray
    score: _np.ndarray
    rank: _np.ndarray
    rotation: _np.ndarray

    @property
    def best(self) -> _np.ndarray:
        """Database indices of rank 1 (the set of best matchings)."""
        return self.db_index[self.rank == 1]

    def __repr__(self) -> str:
        best = self.best.tolist()
        shown = ", ".join(map(str, best[:5])) + (", ..." if len(best) > 5 else "")
        return f"StringMatches({len(self.db_index)} candidates, best [{shown}])"


def match_strings(
    db: list[str],
    queries: list[str],
    config: MatchConfig | None = None,
    *,
    window: int = 1,
    preset: str | None = None,
    **overrides,
) -> list[StringMatches]:
    """String-matching localization of the second paper (``seqtopo match-strings``).

    Every query string (a test point's fingerprint: ``v`` = vertical edge, ``A``..``P`` = colour patch) is
    compared with every database string by algorithm A (weighted global alignment with at most k
    differences), B (k-differences inexact matching) or C (indel distance through the LCS).
    ``config``: a :class:`MatchConfig`; keyword arguments override its fields (``algorithm="B"``,
    ``k=2``, ``cyclic=True``...). ``preset``: a cost table name for A (:func:`preset_names`), applied
    before ``costs`` overrides. ``window``: localize each query with the ``window`` queries ending at it
    (both lists in travel order). Returns one :class:`StringMatches` per query.
    """
    if preset is not None:
        overrides.setdefault("costs", preset_costs(preset))
    config = _config(config, MatchConfig, overrides)
    window = _whole("window", window, 1)
    raw = _core.match_strings(list(db), list(queries), config, window)
    return [StringMatches(*fields) for fields in raw]


del annotations
