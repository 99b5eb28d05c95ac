"""Pictures: load maps, ball-passage tables and load zones (matplotlib, optional).

Install with ``pip install 'fastbearing[plot]'``. matplotlib is imported on
the first plot, never with the package; without a display the Agg backend is
used. Every function returns a ``matplotlib.figure.Figure`` and, given
``out``, also writes it: the format (PNG, SVG or PDF) follows the file
extension, and an existing file is never replaced unless ``overwrite``.

Data are in N, mm, rad. Axis labels and titles carry the units, with a
decimal prefix chosen for readable ticks (kN/mm, MN*mm/rad, mrad);
angles of the geometry (contact angles, azimuths, the cage angle) are
drawn in degrees, as a user types them, tilts (bx, by) in rad or mrad;
``base_units=True`` keeps N, mm, rad as stored, in titles too.

Curves of one panel that coincide (:func:`coincident`) are drawn so that
both stay visible, the later one dashed on top, and its legend entry says
``(coincides with ...)`` (:func:`draw_curves`, also used by
``fastbearing paper``).

Variables (``var``): a Kb entry ``k`` + two of x, y, z, tx, ty (``kxx``,
``kzz``, ``kxty``, ``ktyty``, ...); a displacement component ``dx`` ...
``by`` (q) or a load component ``Fx`` ... ``My`` (f); and every other
variable the file stores over its operating points (and ``row``) with its
``units`` attribute: ``max_ball_load``, ``loaded_balls``, the contact
angles (inner, and outer at speed), ``iterations``, ``residual`` and, in
maps with life, ``L10r``, ``L10``, ``L10r_hours``, ``L10_hours``,
``L10r_row``, ``static_safety`` (:func:`plottable`).
"""

from __future__ import annotations

import contextlib
import math
import os
import sys
from pathlib import Path

import numpy as np

from .. import status as st
from ..dofs import DISPLACEMENT_NAMES, DISPLACEMENT_UNITS, DOF_LABELS as DOF, LOAD_NAMES, LOAD_UNITS, k_entry_units
from ..files import publish, refuse_overwrite

FORMATS = (".png", ".svg", ".pdf")
#: Default picture size in pixels (width, height) and resolution.
DEFAULT_SIZE = (800, 560)
DEFAULT_DPI = 100
ROW_VARIABLES = {"max_ball_load": ("N", "largest ball load"), "loaded_balls": ("1", "loaded balls"),
                 "min_contact_angle": ("rad", "smallest loaded contact angle"),
                 "max_contact_angle": ("rad", "largest loaded contact angle"),
                 "min_outer_contact_angle": ("rad", "smallest loaded outer contact angle"),
                 "max_outer_contact_angle": ("rad", "largest loaded outer contact angle")}
#: Rating-life variables of a map with ``life = true`` (units, description, what the map needs for it); the
#: lives are drawn on a log scale.
LIFE_VARIABLES = {"L10r": ("million revolutions", "rating life L10r", "life = true"),
                  "L10r_row": ("million revolutions", "rating life L10r of a row", "life = true"),
                  "L10": ("million revolutions", "rating life L10 (ISO 281)",
                          "life = true and a bearing with a load rating C (ISO 281)"),
                  "L10r_hours": ("h", "rating life L10r", "life = true and a speed"),
                  "L10_hours": ("h", "rating life L10 (ISO 281)",
                                "life = true, a speed and a bearing with a load rating C (ISO 281)"),
                  "static_safety": ("1", "static safety S0", "life = true")}
LOG_VARIABLES = ("L10r", "L10r_row", "L10", "L10r_hours", "L10_hours")
#: Variables that are angles (stored in rad, as every angle in the files): pictures show them in degrees, as a
#: user types angles (``base_units`` keeps rad).
ANGLE_VARIABLES = ("min_contact_angle", "max_contact_angle", "min_outer_contact_angle", "max_outer_contact_angle")
#: Stored variables drawn through their own names for an entry (kxx, dz, Fx ...), not whole.
_BY_ENTRY = ("K", "q", "f")
NORMALISE = ("none", "first", "mean")
PASSAGE_X = ("angle", "period", "time", "revolutions")
#: The paper's Fig. 13/14 entries, the default of passage plots.
PAPER_ENTRIES = ("kxx", "kzz", "ktyty")
MARKERS = {"DB": "o", "DF": "s", "DT": "^", "single": "x"}
_STYLE = {"font.size": 10, "axes.titlesize": 10, "axes.labelsize": 10, "legend.fontsize": 9,
          "legend.frameon": False, "axes.grid": True, "grid.alpha": 0.35, "lines.linewidth": 1.6,
          "lines.markersize": 5, "image.cmap": "viridis", "savefig.facecolor": "white"}
_SYMBOL = {"x": "x", "y": "y", "z": "z", "tx": r"\theta_x", "ty": r"\theta_y"}
_QUANTITY_UNITS = dict(zip(DISPLACEMENT_NAMES + LOAD_NAMES, DISPLACEMENT_UNITS + LOAD_UNITS))
_PREFIXES = ((1e9, "G"), (1e6, "M"), (1e3, "k"))
#: Curves of one panel closer than this fraction of the panel's value range at every point coincide on the
#: picture (0.5 % is about one line width on a 500-pixel panel): they are drawn so that both stay visible.
COINCIDE_RTOL = 5e-3
#: Line styles of the 1st, 2nd ... curve drawn over an earlier one it coincides with.
_OVER_STYLES = ("--", ":", "-.", (0, (6, 2, 1, 2, 1, 2)))
#: Lines with more points than this get sparse markers, one every _MARK_STEP of the axes diagonal.
_SPARSE = 25
_MARK_STEP = 0.1


# -- matplotlib, figures, files ------------------------------------------------

def _mpl():
    """matplotlib, imported on first use; Agg where there is no display."""
    try:
        import matplotlib
    except ImportError:
        raise ImportError("plots need matplotlib: pip install 'fastbearing[plot]'") from None
    if ("MPLBACKEND" not in os.environ and sys.platform.startswith("linux")
            and not (os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY"))):
        matplotlib.use("Agg")
    return matplotlib


def style():
    """Context manager with fastbearing's plot style (grid, font sizes, viridis)."""
    return _mpl().rc_context(_STYLE)


def new_figure(size=None, dpi: int = DEFAULT_DPI):
    """An empty Figure of ``size`` = (width, height) pixels, constrained layout (no pyplot state)."""
    from matplotlib.figure import Figure

    _mpl()
    w, h = DEFAULT_SIZE if size is None else size
    if not (w >= 50 and h >= 50 and dpi >= 10):
        raise ValueError(f"size must be at least 50x50 pixels and dpi at least 10, got {w}x{h} at {dpi}")
    return Figure(figsize=(w / dpi, h / dpi), dpi=dpi, layout="constrained")


def check_output(out, overwrite: bool = False) -> Path:
    """The output path, checked before any work: a known extension, no silent overwrite."""
    out = Path(out)
    if out.suffix.lower() not in FORMATS:
        raise ValueError(f"output must end in .png, .svg or .pdf (the format follows the extension), "
                         f"got {out.name!r}")
    refuse_overwrite(out, overwrite)
    if not out.parent.is_dir():
        raise ValueError(f"output folder {out.parent} does not exist")
    return out


def save(fig, out, overwrite: bool = False) -> Path:
    """Write ``fig`` to ``out`` (format from the extension), via a temporary name: never half-written."""
    out = check_output(out, overwrite)
    return publish(out, lambda tmp: fig.savefig(tmp, format=out.suffix[1:].lower(), dpi=fig.dpi))


def _figure_legend(fig, handles, **kwargs):
    """One legend for the whole figure, below the panels (constrained layout makes room for it)."""
    try:
        return fig.legend(handles=handles, loc="outside lower center", **kwargs)
    except ValueError:  # matplotlib < 3.7 has no 'outside' placement
        return fig.legend(handles=handles, loc="lower center", **kwargs)


def _wrap(text: str, width: int) -> str:
    """``text`` on lines of about ``width`` characters, broken at spaces outside math ($...$)."""
    words = []
    for word in text.split(" "):
        if words and words[-1].count("$") % 2:  # inside $...$: keep the formula whole
            words[-1] += " " + word
        else:
            words.append(word)
    lines = [""]
    for word in words:
        if lines[-1] and len(lines[-1]) + 1 + len(word) > width:
            lines.append(word)
        else:
            lines[-1] = f"{lines[-1]} {word}" if lines[-1] else word
    return "\n".join(lines)


def fit_ylabels(fig, axes, fill: float = 0.95) -> None:
    """Wrap each y-label longer than its panel is tall onto more lines, so that the labels of panels stacked
    one above the other do not run into each other (a long label beside a short panel: ``plot line --var
    kxx,kzz,min_contact_angle``)."""
    fig.draw_without_rendering()  # lay the figure out: the panels' heights
    for ax in axes:
        label = ax.yaxis.label
        text = label.get_text()
        room = fill * ax.get_window_extent().height
        if " " not in text or label.get_window_extent().height <= room:
            continue
        for width in range(len(text) - 1, 0, -1):
            label.set_text(_wrap(text, width))
            if label.get_window_extent().height <= room:
                break


def _finish(fig, out, overwrite):
    if out is not None:
        save(fig, out, overwrite)
    return fig


# -- names, units, labels --------------------------------------------------------

def k_entry(name: str) -> tuple[int, int]:
    """Row and column of a Kb entry named ``k`` + two of x, y, z, tx, ty (``ktyty`` -> (4, 4))."""
    rest, index = name[1:] if name.startswith("k") else None, []
    while rest:
        label = rest[:2] if rest.startswith("t") else rest[:1]
        if label not in DOF:
            return None
        index.append(DOF.index(label))
        rest = rest[len(label):]
    return tuple(index) if len(index) == 2 else None


def symbol(name: str) -> str:
    """Math-text symbol of a variable or axis: kxty -> k_{x theta_y}, dx -> delta_x, Fx -> F_x."""
    ij = k_entry(name)
    if ij is not None:
        return rf"$k_{{{_SYMBOL[DOF[ij[0]]]}{_SYMBOL[DOF[ij[1]]]}}}$"
    if name in DISPLACEMENT_NAMES:
        return rf"$\{'delta' if name[0] == 'd' else 'beta'}_{name[1]}$"
    if name in LOAD_NAMES:
        return rf"${name[0]}_{name[1]}$"
    return {**ROW_VARIABLES, **LIFE_VARIABLES}.get(name, (None, name.replace("_", " ")))[1]


def plottable(ds) -> list[str]:
    """The variables of ``ds`` that pictures take whole (beside the Kb, q and f entries kxx, dz, Fx ...):
    those with a ``units`` attribute over the operating points, with ``row`` or ``position`` at most."""
    dims = set(case_dims(ds)) | {"row", "position"}
    return [name for name, da in ds.data_vars.items()
            if name not in (*_BY_ENTRY, "status") and _stored_units(da) is not None and set(da.dims) <= dims]


def _stored_units(da) -> str | None:
    """The units of a stored variable: its ``units`` attribute, else (a Dataset built by hand) the units a
    fastbearing variable of its name has; None where neither says."""
    units = da.attrs.get("units")
    if isinstance(units, str):
        return units
    return {**ROW_VARIABLES, **LIFE_VARIABLES}.get(da.name, (None,))[0]


def scale_units(values, units: str, base_units: bool = False) -> tuple[float, str]:
    """Factor and unit text for display: N-based units get k/M/G, small rad -> mrad, small s -> ms."""
    shown = units.replace("*", "\u00b7")
    if base_units or units in ("1", "%"):
        return 1.0, shown
    values = np.asarray(values, dtype=float)
    top = float(np.nanmax(np.abs(values))) if values.size and np.isfinite(values).any() else 0.0
    if units.startswith("N"):
        for limit, prefix in _PREFIXES:
            if top >= limit:
                return 1.0 / limit, prefix + shown
    elif units == "rad" and 0 < top < 0.1:
        return 1e3, "mrad"
    elif units == "s" and 0 < top < 1:
        return 1e3, "ms"
    return 1.0, shown


def variable_units(name: str, values, units: str, base_units: bool = False) -> tuple[float, str]:
    """Factor and unit text for drawing variable ``name`` (:func:`scale_units`; an angle in degrees)."""
    if name in ANGLE_VARIABLES and units == "rad" and not base_units:
        return 180.0 / math.pi, "deg"
    return scale_units(values, units, base_units)


def axis_label(text: str, units: str) -> str:
    """``text (units)``; dimensionless quantities read ``(-)``."""
    return f"{text} ({'-' if units == '1' else units})"


# -- curves that coincide --------------------------------------------------------

def coincident(curves, rtol: float = COINCIDE_RTOL) -> list:
    """For each curve (y arrays over one common x), the index of the first earlier curve it coincides
    with, or None.

    Two curves coincide when they have the same length and the same gaps (NaN) and differ by at most
    ``rtol`` times the range of all the curves' values together (their largest magnitude if that range
    is 0) at every point: on the picture one would hide the other. A curve is compared only with curves
    that coincide with no earlier one, so each group has one first curve.
    """
    ys = [np.asarray(y, dtype=float).ravel() for y in curves]
    values = np.concatenate([y[np.isfinite(y)] for y in ys]) if ys else np.empty(0)
    scale = float(np.ptp(values)) if values.size else 0.0
    if scale == 0.0 and values.size:
        scale = float(np.abs(values).max())
    same = [None] * len(ys)
    for k, y in enumerate(ys):
        ok = np.isfinite(y)
        for j in range(k):
            if (same[j] is None and ys[j].shape == y.shape and np.array_equal(ok, np.isfinite(ys[j]))
                    and np.all(np.abs(y[ok] - ys[j][ok]) <= rtol * scale)):
                same[k] = j
                break
    return same


def draw_curves(ax, x, curves, *, names=None, rtol: float = COINCIDE_RTOL) -> list:
    """Plot ``curves`` = [(label, y, style dict), ...] over a common ``x`` on ``ax``; returns the lines.

    A curve that coincides with an earlier one (:func:`coincident`) is drawn over it (higher z-order)
    dashed, dotted, ... so the first shows through the gaps; its markers sit between the first one's
    (or, where every point has a marker, as larger open rings around them), and its legend label reads
    ``label (coincides with NAME)``, NAME from ``names`` (default: the labels). Lines of more than 25
    points get sparse markers unless the style sets ``markevery``.
    """
    import matplotlib as mpl

    same = coincident([y for _, y, _ in curves], rtol)
    names = list(names) if names is not None else [label for label, _, _ in curves]
    size = {j: 1 + same.count(j) for j in same if j is not None}
    drawn, lines = {}, []
    for (label, y, given), j in zip(curves, same):
        look = dict(given or {})
        marked = look.get("marker") not in (None, "", "None", "none")
        sparse = marked and len(x) > _SPARSE and "markevery" not in look
        if sparse:
            look["markevery"] = (0.0, _MARK_STEP)
        if j is not None:
            m = drawn[j] = drawn.get(j, 0) + 1
            look["linestyle"] = _OVER_STYLES[(m - 1) % len(_OVER_STYLES)]
            look["zorder"] = look.get("zorder", 2.0) + 0.1 * m  # 2: matplotlib's default for lines
            if sparse:
                look["markevery"] = (_MARK_STEP * m / size[j], _MARK_STEP)
            elif marked:
                look["markerfacecolor"] = "none"
                look["markersize"] = look.get("markersize", mpl.rcParams["lines.markersize"]) + 3.0 * m
            label = None if label is None else f"{label} (coincides with {names[j]})"
        lines += ax.plot(x, y, label=label, **look)
    return lines


# -- reading files ---------------------------------------------------------------

@contextlib.contextmanager
def _dataset(source, kind: str):
    """An xarray Dataset of a finished load map (``kind="map"``) or ball-passage table (``"passage"``),
    from a path (closed afterwards) or a Dataset (left open)."""
    if hasattr(source, "data_vars"):
        ds, opened = source, False
    else:
        from ..jobs.loadmap import open_dataset
        from ..jobs.locations import is_url

        path = source if is_url(source) else Path(source)
        if isinstance(path, Path) and not path.exists():
            raise ValueError(f"{path}: file not found")

        ds, opened = open_dataset(path), True  # ValueError if it is not a finished fastbearing file
    try:
        if "K" not in ds or "status" not in ds:
            raise ValueError("not a fastbearing load map or ball-passage file (no K or status variable)")
        is_passage = "position" in ds.dims
        if kind == "map" and is_passage:
            raise ValueError("this is a ball-passage table; plot it with 'plot passage' or 'plot spectrum'")
        if kind == "passage" and not is_passage:
            raise ValueError("this is a load map, not a ball-passage table; plot it with 'plot map' or 'plot line'")
        yield ds
    finally:
        if opened:
            ds.close()


def case_dims(ds) -> list[str]:
    """The file's operating-point axes (grid axes, or ``case`` / ``point``), without ``position``."""
    return [d for d in ds["status"].dims if d != "position"]


def _bearing_title(ds) -> str:
    import json

    try:
        b = json.loads(ds.attrs["bearing_json"])
        return f"{b.get('name') or 'bearing'} {b.get('arrangement', '')}".strip()
    except (KeyError, ValueError):
        return "bearing"


def variable(ds, var: str, row=None):
    """DataArray of ``var`` over the case dims (and ``row`` for per-row variables), with its units."""
    ij = k_entry(var)
    if ij is not None:
        return ds["K"].isel(dof=ij[0], dof_col=ij[1]), k_entry_units(*ij)
    if var in DISPLACEMENT_NAMES:
        return ds["q"].isel(dof=DISPLACEMENT_NAMES.index(var)), _QUANTITY_UNITS[var]
    if var in LOAD_NAMES:
        return ds["f"].isel(dof=LOAD_NAMES.index(var)), _QUANTITY_UNITS[var]
    if var in LIFE_VARIABLES and var not in ds:
        raise ValueError(f"{var} is not in this file: compute the map with {LIFE_VARIABLES[var][2]} in [loadmap]")
    if var in plottable(ds):
        da = ds[var]
        units = _stored_units(da)
        if da.dtype.kind in "iu":
            da = da.astype(float)  # counts: blanks (nan) where a case did not converge
        if "row" in da.dims and row is not None:
            n = ds.sizes["row"]
            if isinstance(row, bool) or not isinstance(row, (int, np.integer)) or not 0 <= row < n:
                raise ValueError(f"row must be an integer in [0, {n - 1}], got {row!r}")
            da = da.isel(row=int(row))
        return da, units
    raise ValueError(f"unknown variable {var!r}; use a Kb entry k + two of {', '.join(DOF)} (kxx, kzz, kxty, "
                     f"ktyty ...), {', '.join(DISPLACEMENT_NAMES)} (q), {', '.join(LOAD_NAMES)} (f) or one of this "
                     f"file's variables: {', '.join(plottable(ds)) or 'none'}"
                     + ("" if "L10r" in ds else f" (maps with life also: {', '.join(LIFE_VARIABLES)})"))


def _axis_units(ds, name: str) -> str:
    return ds[name].attrs.get("units", _QUANTITY_UNITS.get(name, "1"))


def select(ds, da, keep, at=None, default: str = "middle", base_units: bool = False):
    """Fix every case axis not in ``keep`` at the nearest value of ``at[axis]`` (default: the middle
    value, or the first with ``default="first"``); a value beyond the axis's first or last value is a
    ValueError naming the axis and its range, not its edge's point.

    Returns the selected ``da``, the matching solver ``status`` and the operating point as a list of
    'name = value units' texts (for titles; N, mm, rad as stored with ``base_units``).
    """
    dims = case_dims(ds)
    at = dict(at or {})
    unknown = sorted(set(at) - set(dims))
    if unknown:
        raise ValueError(f"unknown axis {unknown[0]!r} in at; this file's axes: {', '.join(dims)}")
    for name in keep:
        if name in at:
            raise ValueError(f"axis {name!r} is plotted; it cannot also be fixed with at")
    fixed, where = {}, []
    for name in dims:
        if name in keep:
            continue
        values = ds[name].values
        if name in at:
            value = at[name]
            if isinstance(value, bool) or not isinstance(value, (int, float, np.number)) or not math.isfinite(value):
                raise ValueError(f"at.{name} must be a finite number, got {value!r}")
            k = _nearest(ds, name, values, value)
        else:
            k = len(values) // 2 if default == "middle" else 0
        fixed[name] = k
        if name in ("case", "point"):  # a table of operating points: name the chosen one's inputs
            where.append(f"{name} {int(values[k])}")
            where += [_value_text(c, float(ds[c].values[k]), _axis_units(ds, c), base_units)
                      for c in LOAD_NAMES + DISPLACEMENT_NAMES
                      if c in ds.coords and ds[c].dims == (name,) and ds[c].values[k] != 0]
        else:
            where.append(_value_text(name, values[k], _axis_units(ds, name), base_units))
    # constant inputs are part of the operating point too
    for name in LOAD_NAMES + DISPLACEMENT_NAMES:
        if name in ds.coords and ds[name].ndim == 0 and float(ds[name]) != 0.0:
            where.append(_value_text(name, float(ds[name]), _axis_units(ds, name), base_units))
    return da.isel(fixed), ds["status"].isel(fixed), where


#: How far beyond an axis's first or last value ``at`` may reach, as a fraction of the axis's grid spacing (of
#: its magnitude for an axis of one value): rounding in a typed value, not a point off the grid (as
#: ``fastbearing export --at``).
AT_TOLERANCE = 1e-9


def _nearest(ds, name: str, values, value: float) -> int:
    """Index of the grid value of axis ``name`` nearest to ``value``; a ValueError naming the axis and its range
    (in its units) when ``value`` lies beyond the axis's first or last value: nearest is for points between
    grid values, not for extrapolation (the edge's point would be drawn as if it were the one asked for)."""
    values = np.asarray(values, dtype=float).reshape(-1)
    low, high = float(values.min()), float(values.max())
    spacing = (high - low) / (len(values) - 1) if len(values) > 1 else 0.0
    tol = AT_TOLERANCE * (spacing or max(abs(low), abs(high), 1.0))
    if not low - tol <= value <= high + tol:
        units = _axis_units(ds, name)
        unit = "" if units in ("", "1") else f" {units}"
        span = f"[{low:g}, {high:g}]" if len(values) > 1 else f"{low:g} only"
        raise ValueError(f"at {name}={value:g} is outside the file's {name} axis {span}{unit} ({len(values)} "
                         "values): give a value within it")
    return int(np.argmin(np.abs(values - value)))


def _value_text(name: str, value: float, units: str, base_units: bool = False) -> str:
    factor, shown = scale_units([value], units, base_units)
    return f"{name} = {value * factor:.4g}" + ("" if units == "1" else f" {shown}")


def _where_text(ds, keep, where) -> str:
    """Title lines: the operating point shown and, where the file has others, how many and how to pick one."""
    text = f"\nat {', '.join(where)}" if where else ""
    others = {d: ds.sizes[d] for d in case_dims(ds) if d not in keep and ds.sizes[d] > 1}
    if others:
        total = math.prod(others.values())
        pick = ",".join(f"{d}=0..{n - 1}" if d in ("case", "point") else f"{d}=VALUE" for d, n in others.items())
        text += f"\n(1 of {total} operating points in the file; choose with --at {pick})"
    return text


def _check_axis(ds, name: str, role: str) -> None:
    dims = case_dims(ds)
    if name not in dims or name in ("case", "point"):
        grid = [d for d in dims if d not in ("case", "point")]
        raise ValueError(f"unknown axis {name!r} for {role}; this file's grid axes: "
                         f"{', '.join(grid) if grid else 'none (a case table has no grid to plot over)'}")
    if ds.sizes[name] < 2:
        raise ValueError(f"axis {name!r} has 1 value; {role} needs at least 2")


# -- load maps ---------------------------------------------------------------------

def plot_map(source, var: str, x: str, y: str, *, at=None, row=None, kind: str = "contour", out=None,
             overwrite: bool = False, size=None, dpi: int = DEFAULT_DPI, base_units: bool = False, levels: int = 15):
    """Contour or heat map of one variable of a load map over two of its grid axes.

    Parameters
    ----------
    source : str, Path or xarray.Dataset
        A finished load-map file (``fastbearing loadmap``) or its dataset.
    var : str
        Kb entry (``kzz``, ``kxty`` ...), q or f component, or a per-row
        summary (without ``row``: over all rows, ``loaded_balls`` summed,
        ``min_contact_angle`` the smallest, the others the largest).
    x, y : str
        Grid axes for the horizontal and vertical directions (e.g. ``Fx``, ``My``).
    at : dict, optional
        Values for the other axes (N, N*mm, mm, rad, rpm as stored); the nearest grid value is used (default:
        the middle one). A value beyond an axis's range is a ValueError.
    kind : {"contour", "heatmap"}
    out : str or Path, optional
        Output file .png, .svg or .pdf.
    size : (int, int), optional
        Width and height in pixels (default 800 x 560).

    Cases that did not converge are left blank.
    """
    if kind not in ("contour", "heatmap"):
        raise ValueError(f"kind must be 'contour' or 'heatmap', got {kind!r}")
    if out is not None:
        check_output(out, overwrite)
    with _dataset(source, "map") as ds:
        _check_axis(ds, x, "a map")
        _check_axis(ds, y, "a map")
        if x == y:
            raise ValueError(f"x and y must be two different axes, got {x!r} twice")
        da, units = variable(ds, var, row)
        da, status, where = select(ds, da, (x, y), at, base_units=base_units)
        ok = st.converged_mask(status.transpose(y, x).values)
        if "row" in da.dims:  # a per-row variable over all rows: the bearing's total, smallest or largest
            da = (da.sum if var == "loaded_balls" else da.min if var.startswith("min_") or var == "L10r_row"
                  else da.max)("row")
        z = np.where(ok, da.transpose(y, x).values, np.nan)
        log = var in LOG_VARIABLES
        unbounded = int(np.isinf(z).sum())
        z = np.where(np.isinf(z), np.nan, z)  # an unloaded case lives for ever: blank, and said so
        xv, yv = ds[x].values, ds[y].values
        with style():
            fig = new_figure(size, dpi)
            ax = fig.add_subplot()
            fx, ux = scale_units(xv, _axis_units(ds, x), base_units)
            fy, uy = scale_units(yv, _axis_units(ds, y), base_units)
            fz, uz = (1.0, units) if var in LIFE_VARIABLES else variable_units(var, z, units, base_units)
            finite = z[np.isfinite(z)]
            flat = finite.size == 0 or np.ptp(finite) <= 1e-12 * max(1.0, np.abs(finite).max())
            logbar = log and finite.size and finite.min() > 0 and not flat
            if logbar:
                from matplotlib import colors, ticker

                if kind == "heatmap":
                    mesh = ax.pcolormesh(xv * fx, yv * fy, z, shading="nearest", norm=colors.LogNorm())
                else:
                    mesh = ax.contourf(xv * fx, yv * fy, z, locator=ticker.LogLocator(subs=(1.0, 2.0, 5.0)),
                                       norm=colors.LogNorm())
                    ax.contour(mesh, colors="k", linewidths=0.4, alpha=0.6)
            elif kind == "heatmap" or flat:
                mesh = ax.pcolormesh(xv * fx, yv * fy, z * fz, shading="nearest")
            else:
                mesh = ax.contourf(xv * fx, yv * fy, z * fz, levels=levels)
                ax.contour(mesh, colors="k", linewidths=0.4, alpha=0.6)
            bar = fig.colorbar(mesh, ax=ax)
            if logbar:
                _label_log_colorbar(bar, finite.min(), finite.max())
            per_row = var in ds.data_vars and "row" in ds[var].dims
            what = symbol(var) + ("" if row is None or not per_row else f", row {row}")
            bar.set_label(axis_label(what, uz))
            ax.set_xlabel(axis_label(symbol(x), ux))
            ax.set_ylabel(axis_label(symbol(y), uy))
            ax.grid(False)
            blank = int((~ok).sum())
            ax.set_title(f"{what} of {_bearing_title(ds)}" + (f" at {', '.join(where)}" if where else "")
                         + (f"\n{blank} case(s) not converged (blank)" if blank else "")
                         + (f"\n{unbounded} {'unloaded or 0 rpm' if var.endswith('_hours') else 'unloaded'} "
                            "case(s): unbounded life (blank)" if unbounded else ""))
            return _finish(fig, out, overwrite)


def _label_log_colorbar(bar, low: float, high: float) -> None:
    """Label a logarithmic colour bar between its decades too (1, 2, 5 x 10^n; every digit under a decade's
    span): with the decades alone a map spanning one or two decades shows only one or two numbers."""
    from matplotlib import ticker

    decades = math.log10(high / low)
    subs = np.arange(1.0, 10.0) if decades < 1.0 else (1.0, 2.0, 5.0) if decades <= 5.0 else (1.0,)
    bar.locator = ticker.LogLocator(subs=subs)
    bar.formatter = ticker.LogFormatterSciNotation(labelOnlyBase=False, minor_thresholds=(math.inf, math.inf))
    bar.minorlocator = ticker.LogLocator(subs=np.arange(2.0, 10.0))
    bar.update_ticks()


def _variables_to_draw(var, out, overwrite: bool) -> list[str]:
    """The variables a picture draws (one name or several; at least one), its output checked before any work
    (an existing picture is replaced only with ``overwrite``)."""
    names = [var] if isinstance(var, str) else list(var)
    if not names:
        raise ValueError("var must name at least one variable")
    if out is not None:
        check_output(out, overwrite)
    return names


def plot_lines(source, var, x: str, *, at=None, row=None, series=None, out=None, overwrite: bool = False,
               size=None, dpi: int = DEFAULT_DPI, base_units: bool = False):
    """Line plots of one or more variables of a load map along one grid axis.

    One panel per variable (shared ``x``). ``series`` names a second axis:
    one line per value of it (up to 12). A per-row variable without ``row``
    gets one line per row. ``at`` fixes the other axes (nearest value;
    default the middle one). Non-converged cases are gaps.
    """
    names = _variables_to_draw(var, out, overwrite)
    with _dataset(source, "map") as ds:
        _check_axis(ds, x, "a line plot")
        keep = (x,)
        if series is not None:
            _check_axis(ds, series, "series")
            if series == x:
                raise ValueError(f"series must be another axis than x ({x!r})")
            if ds.sizes[series] > 12:
                raise ValueError(f"series axis {series!r} has {ds.sizes[series]} values; at most 12 lines per panel")
            keep = (x, series)
        xv = ds[x].values
        with style():
            fig = new_figure(size, dpi)
            axes = fig.subplots(len(names), 1, sharex=True, squeeze=False)[:, 0]
            fx, ux = scale_units(xv, _axis_units(ds, x), base_units)
            where = []
            for ax, name in zip(axes, names):
                da, units = variable(ds, name, row)
                da, status, where = select(ds, da, keep, at, base_units=base_units)
                ok = st.converged_mask(status.values)
                values = np.where(ok[..., None] if "row" in da.dims else ok, da.values, np.nan)
                # put x first, then the series axis, then row
                order = [da.dims.index(d) for d in keep] + ([da.dims.index("row")] if "row" in da.dims else [])
                values = values.transpose(order).reshape(len(xv), -1)
                labels = []
                if series is not None:
                    fs, us = scale_units(ds[series].values, _axis_units(ds, series), base_units)
                    labels = [f"{symbol(series)} = {v * fs:.4g} {us}" for v in ds[series].values]
                if "row" in da.dims:
                    rows = [f"row {r}" for r in range(ds.sizes["row"])]
                    labels = [f"{a}, {b}" for a in labels for b in rows] if labels else rows
                fv, uv = variable_units(name, values, units, base_units)
                look = {"marker": "o" if len(xv) <= _SPARSE else None}
                if name in LOG_VARIABLES:  # an unbounded life (unloaded, 0 rpm) is a gap; lives on a log scale
                    values = np.where(np.isinf(values), np.nan, values)
                draw_curves(ax, xv * fx, [(labels[k] if labels else None, values[:, k] * fv, look)
                                          for k in range(values.shape[1])])
                finite = values[np.isfinite(values)]
                if name in LOG_VARIABLES and finite.size and finite.min() > 0:
                    ax.set_yscale("log")
                ax.set_ylabel(axis_label(symbol(name), uv))
                if len(labels) > 4:  # beside the panel: inside it such a legend hides curves
                    ax.legend(fontsize=8, loc="center left", bbox_to_anchor=(1.01, 0.5))
                elif labels:
                    ax.legend(fontsize=8)
            axes[-1].set_xlabel(axis_label(symbol(x), ux))
            axes[0].set_title(f"{_bearing_title(ds)}" + (f" at {', '.join(where)}" if where else ""))
            fit_ylabels(fig, axes)
            return _finish(fig, out, overwrite)


# -- ball passage --------------------------------------------------------------------

def passage_curve(ds, var: str, *, at=None, x: str = "angle", normalise: str = "none",
                  base_units: bool = False):
    """One entry of a passage table over one whole period (position 0 repeated at the end).

    Returns (x values, y values, x label, y label, operating-point text list) with display
    scaling applied. ``normalise``: ``"first"`` divides by the value at position 0 (the
    paper's Figs. 13 and 14), ``"mean"`` by the mean over the period, ``"none"`` keeps units.
    """
    if normalise not in NORMALISE:
        raise ValueError(f"normalise must be one of {', '.join(NORMALISE)}, got {normalise!r}")
    if x not in PASSAGE_X:
        raise ValueError(f"x must be one of {', '.join(PASSAGE_X)}, got {x!r}")
    da, units = variable(ds, var)
    if "row" in da.dims:
        raise ValueError(f"{var} is per row; passage plots take Kb entries, q or f components")
    da, status, where = select(ds, da, ("position",), at, default="first", base_units=base_units)
    values = np.where(st.converged_mask(status.values), da.values, np.nan)
    over_revolutions = "shaft_angle" in ds  # a table over shaft revolutions (local defects): no closing point
    if over_revolutions:
        angle = ds["cage_angle"].values
        turns = ds["shaft_angle"].values / (2 * math.pi)
    else:
        values = np.append(values, values[0])
        angle = np.append(ds["cage_angle"].values, float(ds.attrs["period_rad"]))
    if x == "revolutions" or (x == "period" and over_revolutions):
        if not over_revolutions:
            raise ValueError("x = revolutions needs a table over shaft revolutions ([passage] revolutions)")
        xv, xunits, xtext = turns, "1", "shaft revolutions"
    elif x == "time" and over_revolutions:
        if "time" not in ds:
            raise ValueError("this table has no time axis: give speed (or shaft_speed) in [passage]")
        xv, xunits, xtext = ds["time"].values, "s", "time"
    elif x == "angle":  # degrees, as a user types angles (base_units: rad, as stored)
        xv, xunits = (angle, "rad") if base_units else (np.degrees(angle), "deg")
        xtext = r"cage angle $\psi_c$"
    elif x == "period":
        xv, xunits, xtext = angle / float(ds.attrs["period_rad"]), "1", "ball passage period"
    else:
        if "time" not in ds:
            raise ValueError("this table has no time axis: give shaft_speed, ball_diameter and pitch_diameter "
                             "in [passage]")
        xv, xunits, xtext = angle / (2 * math.pi * float(ds.attrs["cage_frequency_hz"])), "s", "time"
    fx, ux = scale_units(xv, xunits, base_units)
    if normalise == "none":
        fy, uy = scale_units(values, units, base_units)
        ylabel = axis_label(symbol(var), uy)
    else:
        ref = values[0] if normalise == "first" else np.nanmean(values[:-1])
        if not np.isfinite(ref) or ref == 0:
            raise ValueError(f"{var} is zero at this operating point; it cannot be normalised")
        values, fy = values / ref, 1.0
        ylabel = axis_label(symbol(var) + (r" / $k(\psi_c = 0)$" if normalise == "first" else " / mean"), "1")
    return xv * fx, values * fy, axis_label(xtext, ux), ylabel, where


def defect_passes(ds) -> list[tuple[str, np.ndarray]]:
    """When each local defect of a table over shaft revolutions meets an element, in shaft revolutions from
    position 0: (label, revolutions) per defect, from the file's attributes (the defects, the fault orders,
    the first element's azimuth). A race defect meets the next element every 1/BPFO (outer race) or 1/BPFI
    (inner race) revolutions with the inner ring turning, a ball's defect a race every 1/(2 BSF)."""
    if "defects" not in ds.attrs or "shaft_angle" not in ds:
        return []
    import json

    span = float(ds["shaft_angle"].values[-1]) / (2 * math.pi)
    order = {k: float(ds.attrs[f"fault_frequency_{k}_order"]) for k in ("FTF", "BPFO", "BPFI", "BSF")}
    z = order["BPFO"] + order["BPFI"]  # the element count: BPFO + BPFI = Z
    pitch = 2 * math.pi / round(z)
    first = math.radians(float(ds.attrs.get("first_element_angle_deg", 0.0)))
    inner_turns = ds.attrs.get("rotating_ring", "inner") == "inner"
    out = []
    for d in json.loads(ds.attrs["defects"]):
        phi = math.radians(d["angle"])
        if d["race"] == "ball":
            every, start = 1.0 / (2 * order["BSF"]), (phi % (2 * math.pi)) / (2 * math.pi * order["BSF"])
            start %= every
            label = f"ball {d['element']} defect meets a race"
        else:
            # the angle between the defect and the balls closes at the pass order's rate (per element pitch)
            rate = order["BPFO"] if d["race"] == "outer" else order["BPFI"]
            moves_with_cage = (d["race"] == "outer") == inner_turns  # the defect's race stands still
            gap = ((phi - first) if moves_with_cage else (first - phi)) % pitch
            every, start = 1.0 / rate, gap / pitch / rate
            label = f"{d['race']}-race defect passed"
        out.append((label, np.arange(start, span + 1e-12, every)))
    return out


def _mark_defect_passes(ds, axes, x: str, base_units: bool) -> None:
    """Dotted vertical lines where a defect meets an element (x in shaft revolutions or in s)."""
    passes = defect_passes(ds)
    if not passes or x not in ("revolutions", "period", "time"):
        return
    per_turn = 1.0
    if x == "time":
        per_turn = 60.0 / float(ds.attrs["shaft_speed_rpm"])
        per_turn *= scale_units(np.array([per_turn]), "s", base_units)[0]
    for k, (label, turns) in enumerate(passes):
        for ax in axes:
            for j, t in enumerate(turns):
                ax.axvline(t * per_turn, color=f"C{k + 3}", linestyle=":", linewidth=1.0,
                           label=label if (ax is axes[0] and j == 0) else None)
    axes[0].legend(loc="lower right", fontsize="small", framealpha=0.95)


def plot_passage(source, var=PAPER_ENTRIES, *, at=None, x: str = "angle", normalise: str = "none", out=None,
                 overwrite: bool = False, size=None, dpi: int = DEFAULT_DPI, base_units: bool = False):
    """Kb entries over one ball-pass period of a ball-passage table.

    ``x``: ``"angle"`` (cage angle, deg; rad with ``base_units``), ``"period"`` (fraction of the
    period, as in the paper) or ``"time"`` (s, tables with a shaft speed).
    Normalised entries (``"first"``: by the value at position 0, the paper's
    Figs. 13-14; ``"mean"``) share one panel; absolute entries get one panel
    each. ``at`` picks the operating point (nearest value; default the first).
    """
    names = _variables_to_draw(var, out, overwrite)
    with _dataset(source, "passage") as ds:
        curves = [passage_curve(ds, n, at=at, x=x, normalise=normalise, base_units=base_units) for n in names]
        positions = ds.sizes["position"]
        with style():
            fig = new_figure(size, dpi)
            shared = normalise != "none"
            axes = fig.subplots(1 if shared else len(names), 1, sharex=True, squeeze=False)[:, 0]
            # one marker per computed cage position: the closing point (position 0 again) has none
            line = {"marker": "o", "markevery": slice(0, positions)} if positions <= 40 else {}
            panels = [[(symbol(n), c[1], line) for n, c in zip(names, curves)]] if shared else \
                [[(symbol(n), c[1], line)] for n, c in zip(names, curves)]
            for ax, panel in zip(axes, panels):
                draw_curves(ax, curves[0][0], panel)
            for ax, (xv, yv, xl, yl, where) in zip(axes, curves):
                ax.set_ylabel(axis_label("k / k at position 0" if normalise == "first" else "k / mean over the period",
                                         "1") if shared and len(names) > 1 else yl)
            if shared and len(names) > 1:
                axes[0].legend()
            axes[-1].set_xlabel(curves[0][2])
            if "shaft_angle" in ds:
                revolutions = int(ds.attrs["revolutions"])
                axes[0].set_title(f"{_bearing_title(ds)}, {revolutions} shaft revolution"
                                  f"{'' if revolutions == 1 else 's'}, {positions} positions"
                                  + _where_text(ds, ("position",), curves[0][4]))
                _mark_defect_passes(ds, axes, x, base_units)
            else:
                axes[0].set_title(f"{_bearing_title(ds)}, one ball-pass period (Z = {ds.attrs['period_order']}), "
                                  f"{positions} cage positions" + _where_text(ds, ("position",), curves[0][4]))
            fit_ylabels(fig, axes)
            return _finish(fig, out, overwrite)


def plot_spectrum(source, var=PAPER_ENTRIES, *, at=None, normalise: str = "mean", log: bool = True, orders=False,
                  out=None,
                  overwrite: bool = False, size=None, dpi: int = DEFAULT_DPI, base_units: bool = False):
    """Harmonic spectrum of Kb entries of a ball-passage table: amplitude A_h of harmonics h >= 1.

    ``normalise="mean"`` shows A_h in % of the mean A_0 (all entries in one
    panel); ``"none"`` shows A_h in the entry's units (one panel each). The
    horizontal axis is the frequency (Hz) when the table has a shaft speed,
    else the order of the shaft speed for a table over shaft revolutions,
    else the harmonic order of the ball-pass frequency. Fault frequencies the
    file's attributes hold (``fault_frequency_<name>_hz`` / ``_order``, see
    :func:`fault_marks`) are marked as labelled vertical lines in the axis's
    units; a file without them plots without marks.
    """
    if normalise not in ("none", "mean"):
        raise ValueError(f"normalise must be 'none' or 'mean' for a spectrum, got {normalise!r}")
    names = _variables_to_draw(var, out, overwrite)
    with _dataset(source, "passage") as ds:
        for name in names:
            if k_entry(name) is None:
                raise ValueError(f"unknown variable {name!r} for a spectrum; use Kb entries such as kxx, kzz, ktyty")
        H = ds.sizes["harmonic"] - 1
        if H < 1:
            raise ValueError("this table keeps no harmonics above the mean (harmonics = 0)")
        # ``orders`` (a table over shaft revolutions): in orders of the shaft speed even with a speed
        if orders and "order" not in ds:
            raise ValueError("orders needs a table over shaft revolutions ([passage] revolutions); a one-period "
                             "table's harmonics are orders of the ball-pass frequency")
        has_f = "frequency" in ds and not orders
        # a table over shaft revolutions without a speed: each harmonic's order of the shaft speed
        has_order = not has_f and "order" in ds
        axis = "hz" if has_f else "order" if has_order else "harmonic"
        h = np.arange(1, H + 1)
        xv = ds["frequency"].values[1:] if has_f else ds["order"].values[1:] if has_order else h.astype(float)
        with style():
            fig = new_figure(size, dpi)
            shared = normalise == "mean"
            axes = fig.subplots(1 if shared else len(names), 1, sharex=True, squeeze=False)[:, 0]
            width = 0.8 / (len(names) if shared else 1)
            step = float(xv[1] - xv[0]) if H > 1 else 1.0
            where = []
            for k, name in enumerate(names):
                i, j = k_entry(name)
                amp, _, where = select(ds, ds["K_amplitude"].isel(dof=i, dof_col=j), ("harmonic",), at,
                                       default="first", base_units=base_units)
                a = amp.values
                if shared:
                    if a[0] == 0:
                        raise ValueError(f"{name} has zero mean at this operating point; use normalise='none'")
                    y, ylabel = a[1:] / abs(a[0]) * 100.0, axis_label("amplitude / mean", "%")
                else:
                    fy, uy = scale_units(a[1:], k_entry_units(i, j), base_units)
                    y, ylabel = a[1:] * fy, axis_label(f"amplitude of {symbol(name)}", uy)
                ax = axes[0 if shared else k]
                offset = (k - (len(names) - 1) / 2) * width * step if shared else 0.0
                ax.bar(xv + offset, np.where(y > 0, y, np.nan) if log else y, width=width * step, label=symbol(name))
                if log:
                    ax.set_yscale("log")
                ax.set_ylabel(ylabel)
            beyond = _mark_fault_frequencies(axes, fault_marks(ds, axis), float(xv[-1]) + step)
            if shared:
                axes[0].legend()
            axes[-1].set_xlabel((axis_label("frequency", "Hz") if has_f else
                                 axis_label("order of the shaft speed", "1") if has_order else
                                 axis_label("harmonic order of the ball-pass frequency", "1"))
                                + (f"; beyond the axis: {', '.join(beyond)}" if beyond else ""))
            revolutions = _attr_number(ds.attrs, "revolutions")
            span = (f"{revolutions:g} shaft revolution{'s' if revolutions != 1 else ''}" if revolutions
                    else "the ball passage")
            axes[0].set_title(f"{_bearing_title(ds)}: harmonics of Kb over {span}"
                              + _where_text(ds, ("harmonic",), where))
            return _finish(fig, out, overwrite)


#: The fault frequencies a passage file's attributes may hold (fault_frequency_<name>_hz and _order) and their
#: labels on the spectrum.
FAULT_LABELS = {"FTF": "FTF", "BPFO": "BPFO", "BPFI": "BPFI", "BSF": "BSF", "ball_defect": "ball defect"}


def _attr_number(attrs, key):
    """A finite float attribute, or None (absent, not a number, or not finite)."""
    try:
        value = float(np.asarray(attrs[key]).reshape(-1)[0])
    except (KeyError, TypeError, ValueError, IndexError):
        return None
    return value if math.isfinite(value) else None


def fault_marks(ds, axis: str) -> list[tuple[str, float]]:
    """(label, x) of each fault frequency (FTF, BPFO, BPFI, BSF, ball defect) a ball-passage file's
    attributes hold, in the spectrum's horizontal units ``axis``; [] where it holds none.

    ``"hz"`` (the table has a shaft speed): x in Hz, from ``fault_frequency_<name>_hz``, else from
    ``fault_frequency_<name>_order`` times the file's ``shaft_speed_rpm`` / 60. ``"order"`` (a table over
    shaft revolutions without a speed): x = the stored order, in multiples of the shaft speed.
    ``"harmonic"`` (a table over one ball-pass period without a speed): x in harmonics of the ball-pass
    frequency: the order divided by the ball-pass order ``period_order`` x FTF order (the cage turns at
    FTF, one table period per ball pass).
    """
    attrs = ds.attrs
    if axis == "hz":  # orders -> Hz where a file holds orders only
        rpm = _attr_number(attrs, "shaft_speed_rpm")
        scale = None if rpm is None or rpm <= 0 else rpm / 60.0
    elif axis == "order":
        scale = 1.0
    else:  # orders -> harmonics of the ball-pass frequency
        ftf, period = _attr_number(attrs, "fault_frequency_FTF_order"), _attr_number(attrs, "period_order")
        scale = None if ftf is None or period is None or ftf <= 0 or period <= 0 else 1.0 / (period * ftf)
    out = []
    for name, label in FAULT_LABELS.items():
        x = _attr_number(attrs, f"fault_frequency_{name}_hz") if axis == "hz" else None
        if x is None:
            order = _attr_number(attrs, f"fault_frequency_{name}_order")
            x = None if order is None or scale is None else order * scale
        if x is not None and x > 0:
            out.append((label, x))
    return out


def _mark_fault_frequencies(axes, marks, upper: float) -> list[str]:
    """Dashed vertical lines at the fault frequencies ``marks`` ((label, x), :func:`fault_marks`) up to
    ``upper`` on every panel, labelled at the top of the top panel (left of the line; right of it where the
    previous label would touch); the labels of those beyond ``upper``."""
    shown = sorted((m for m in marks if m[1] <= upper), key=lambda m: m[1])
    beyond = [label for label, x in marks if x > upper]
    if not shown:
        return beyond
    for _, x in shown:
        for ax in axes:
            ax.axvline(x, color="0.35", linestyle="--", linewidth=0.9, zorder=1.5)
    top = axes[0]
    low, high = top.get_xlim()
    top.set_xlim(max(low, 0.0), high)  # a mark near 0 (FTF) asks for no negative frequencies
    low, high = top.get_xlim()
    last, side = -math.inf, "right"
    for label, x in shown:
        # labels closer than 3 % of the axis take both sides of their lines
        side = "left" if side == "right" and (x - last) / (high - low) < 0.03 else "right"
        top.text(x, 0.98, label, transform=top.get_xaxis_transform(), rotation=90, ha=side, va="top",
                 fontsize="small", color="0.2", zorder=3,
                 bbox={"facecolor": "white", "edgecolor": "none", "alpha": 0.75, "pad": 1.5})
        last = x
    return beyond


# -- load zone ------------------------------------------------------------------------

def _element_name(row) -> str:
    """One of a row's elements in words: "ball", "roller" (its ``element_word``'s first word, singular)."""
    word = row.element_word.split()[0]  # "balls", "rollers"; "balls (one contact pair)"
    return word[:-1] if word.endswith("s") else word


def plot_load_zone(bearing, q, *, title: str | None = None, out=None, overwrite: bool = False, size=None,
                   dpi: int = DEFAULT_DPI):
    """Polar plot of the element (ball or roller) loads Q (N) against azimuth psi (deg), one panel per row
    (the load zone). Each row's texts name its own elements (``element_word``: balls, rollers).

    Parameters
    ----------
    bearing : Bearing
    q : sequence of 5 floats
        Displacement (dx, dy, dz, bx, by) in mm and rad, e.g. ``fb.solve(bearing, f).q``.
    title : str, optional
        Figure title (default: the bearing and q).
    """
    from matplotlib.ticker import MaxNLocator

    from ..analysis.contacts import ball_contacts

    if out is not None:
        check_output(out, overwrite)
    contacts = ball_contacts(bearing, q)       # every ball, then every roller (its total load)
    Q, alpha, psi, row_of = contacts.load, contacts.contact_angle, contacts.azimuth, contacts.row
    n = bearing.n_rows
    top = float(Q.max()) * 1.15 if Q.max() > 0 else 1.0
    with style():
        fig = new_figure(size or (max(600, 400 * min(n, 4)), 520 * math.ceil(n / 4)), dpi)
        cols = min(n, 4)
        for r, row in enumerate(bearing.rows):
            ax = fig.add_subplot(math.ceil(n / cols), cols, r + 1, projection="polar")
            sel = row_of == r
            p, load = psi[sel], Q[sel]
            order = np.argsort(p)
            ring = np.append(p[order], p[order][0] + 2 * np.pi)
            ax.fill(ring, np.append(load[order], load[order][0]), alpha=0.2, color="C0")
            ax.plot(ring, np.append(load[order], load[order][0]), color="C0", linewidth=1.0)
            for a, v in zip(p, load):
                ax.plot([a, a], [0, v], color="C0", linewidth=1.2)
            loaded = load > 0
            one = _element_name(row)  # ball, roller
            handles = ax.plot(p[loaded], load[loaded], "o", color="C0", markersize=5,
                              label=f"loaded {one} (radius: its load Q)")
            handles += ax.plot(p, np.full(p.size, top), "o", color="0.6", markersize=3, clip_on=False,
                               label=f"{one} positions: every {one} of the row, loaded or not (on the rim)")
            ax.set_ylim(0, top)
            ax.set_thetagrids(np.arange(0, 360, 45), [f"{d}\u00b0" for d in range(0, 360, 45)])
            ax.yaxis.set_major_locator(MaxNLocator(4))
            ax.set_rlabel_position(22.5)
            ax.tick_params(axis="y", labelsize=8)
            ax.set_xlabel(axis_label(r"azimuth $\psi$ from x toward y", "deg") + f";  radius: {one} load Q (N)",
                          fontsize=8)
            a_loaded = alpha[sel][loaded]
            angles = (f"\ncontact angle {np.degrees(a_loaded.min()):.1f} to {np.degrees(a_loaded.max()):.1f} deg"
                      if loaded.any() else "")
            ax.set_title(f"row {r}: z = {row.axial_offset:g} mm, contact direction {row.contact_direction:+d}\n"
                         f"{int(loaded.sum())} of {row.n_elements} {row.element_word}"
                         f" loaded, max Q = {load.max():.4g} N"
                         + angles, fontsize=9)
        words = {_element_name(row) for row in bearing.rows}
        if len(words) > 1:  # rows of balls and of rollers: the legend speaks of both
            either = " or ".join(sorted(words))
            for h in handles:  # the last row's
                h.set_label(h.get_label().replace(one, either))
        _figure_legend(fig, handles, ncol=2 if n > 1 else 1)
        q = np.asarray(q, dtype=float)
        # rounding noise of components that vanish by symmetry reads as 0
        size_q = max(np.abs(q[:3]).max(), bearing.length_scale * np.abs(q[3:]).max(), 1e-300)
        q = np.where(np.abs(q) < 1e-12 * size_q, 0.0, q)
        fig.suptitle(title or f"Load zone of {bearing.name or 'bearing'} ({bearing.arrangement})\nat q = "
                     f"({q[0]:.4g}, {q[1]:.4g}, {q[2]:.4g}) mm, ({q[3]:.4g}, {q[4]:.4g}) rad", fontsize=10)
        return _finish(fig, out, overwrite)
