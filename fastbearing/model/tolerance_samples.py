"""Tolerance zones sampled (issue 44 item 6, its model half): each sample's shaft, ring and housing diameters
and its unmounted clearance drawn uniformly within their zones, and the operating diametral clearance they
give, for a million samples at once.

The zones come from the bearing's ``[bearing.mounting]`` (model/mounted.py):

- a shaft fit class (``shaft_fit = "k5"``): the shaft diameter's ISO 286-2 deviation and the ring bore's
  ISO 492 Normal-class deviation, each drawn on its own; the interference is their difference. A typed
  ``shaft_interference`` is not a zone: every sample takes it;
- the housing likewise (``housing_fit``: the ring OD's ISO 492 and the housing bore's ISO 286-2 deviations);
- ``diametral_clearance`` as an ISO 5753-1 group or a range [min, max]: the unmounted clearance.

The operating clearance is model/mounting.mount_row's budget. It is linear in each fit's operating
interference while the fit holds (Lame: the raceway moves by a fixed compliance times the fit pressure) and
stops at zero pressure where the fit is lost, so one probe of mount_row gives the coefficients and the
samples need no loop (:func:`operating_clearances`; tests/test_tolerance_samples.py checks every sample
against mount_row itself).

Draws are reproducible: the same seed gives the same samples, whatever the blocks they are drawn in
(:func:`draw`: sample i comes from the generator of its block of :data:`DRAW_BLOCK`, seeded by (seed,
block)), so a resumed or parallel job draws what a single pass would. Units: mm (diametral), rpm.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from .. import validate
from . import tolerances
from .mounted import _mount

#: Samples drawn from one generator (seeded by (seed, block index)): the unit of reproducibility.
DRAW_BLOCK = 65536

#: The sampled inputs, in the order they are drawn from each block's generator (deviations in mm).
ZONE_NAMES = ("shaft_diameter_deviation", "bore_deviation", "outer_diameter_deviation", "housing_bore_deviation",
              "unmounted_diametral_clearance", "ball_diameter_deviation")


@dataclass(frozen=True)
class Zone:
    """One sampled input: uniform on [low, high] (mm), from ``source`` (the standard and its row); ``count``
    values a sample (each ball's diameter deviation: one per ball; (n, count) draws), None: one value, (n,)."""

    name: str
    low: float
    high: float
    source: str
    count: int | None = None


def ball_zone(bearing, variation: float) -> Zone:
    """Each ball's diameter deviation, uniform on [-variation/2, +variation/2] (mm): a ball set whose diameters
    spread over ``variation`` (e.g. the lot diameter variation of a ball grade, ISO 3290-1), one value per ball
    (ball rows only)."""
    variation = validate.number(variation, "ball_diameter_variation", low=0.0, units="mm")
    return Zone("ball_diameter_deviation", -0.5 * variation, 0.5 * variation,
                f"each ball uniform within a diameter variation of {1000.0 * variation:g} um", bearing.n_balls)


def tolerance_zones(bearing) -> tuple[Zone, ...]:
    """The zones a bearing's ``[bearing.mounting]`` and clearance give, in :data:`ZONE_NAMES` order (absent
    ones left out). A ValueError naming the field when the bearing has nothing to sample."""
    mounting = getattr(bearing, "mounting", None)
    geometry = getattr(bearing, "geometry", None)
    if mounting is None or geometry is None:
        raise validate.FieldError("bearing.mounting", "is needed to sample tolerance zones: give fit classes "
                                  "(shaft_fit, housing_fit) and/or diametral_clearance as a group or range",
                                  show_value=False)
    zones = []
    d, D = geometry.bore, geometry.outer_diameter
    if mounting.given and mounting.shaft_fit is not None:
        upper, lower = tolerances.shaft_deviation(mounting.shaft_fit, d, size_field="bearing.geometry.bore")
        zones.append(Zone("shaft_diameter_deviation", lower, upper, f"ISO 286-2 {mounting.shaft_fit}, d = {d:g} mm"))
        upper, lower = tolerances.bore_tolerance(d, field="bearing.geometry.bore")
        zones.append(Zone("bore_deviation", lower, upper, f"ISO 492 Normal class bore, d = {d:g} mm"))
    if mounting.given and mounting.housing_fit is not None:
        upper, lower = tolerances.outer_diameter_tolerance(D, field="bearing.geometry.outer_diameter")
        zones.append(Zone("outer_diameter_deviation", lower, upper, f"ISO 492 Normal class OD, D = {D:g} mm"))
        upper, lower = tolerances.housing_deviation(mounting.housing_fit, D,
                                                    size_field="bearing.geometry.outer_diameter")
        zones.append(Zone("housing_bore_deviation", lower, upper, f"ISO 286-2 {mounting.housing_fit}, D = {D:g} mm"))
    if mounting.clearance_range is not None:
        low, high = mounting.clearance_range
        source = (f"ISO 5753-1 {mounting.clearance_group}, d = {d:g} mm" if mounting.clearance_group
                  else "bearing.geometry.diametral_clearance range")
        zones.append(Zone("unmounted_diametral_clearance", low, high, source))
    if not zones:
        raise validate.FieldError("bearing.mounting", "has no tolerance zone to sample: give a fit class "
                                  "(shaft_fit or housing_fit) or diametral_clearance as a group or [min, max]",
                                  show_value=False)
    return tuple(zones)


def draw(zones, n: int, seed: int, first: int = 0) -> dict[str, np.ndarray]:
    """Samples first .. first+n-1 of ``zones`` (n,) each, mm; uniform within each zone, independent.

    Sample i is the same whatever ``first`` and ``n`` cover it: block b = i // DRAW_BLOCK draws all its
    samples' zones from ``np.random.default_rng((seed, b))``, zone by zone in :data:`ZONE_NAMES` order (a zone
    of a ``count`` gives (n, count) values)."""
    n = validate.integer(n, "samples", low=0)
    first = validate.integer(first, "first", low=0)
    seed = validate.integer(seed, "seed", low=0)
    out = {z.name: np.empty((n, z.count) if z.count is not None else n) for z in zones}
    i = first
    while i < first + n:
        block = i // DRAW_BLOCK
        start = block * DRAW_BLOCK
        stop = min(start + DRAW_BLOCK, first + n)
        rng = np.random.default_rng((seed, block))
        for z in sorted(zones, key=lambda z: ZONE_NAMES.index(z.name)):
            u = rng.random((DRAW_BLOCK, z.count) if z.count is not None else DRAW_BLOCK)[i - start:stop - start]
            out[z.name][i - first:stop - first] = z.low + (z.high - z.low) * u
        i = stop
    return out


def interferences(bearing, samples: dict) -> tuple[np.ndarray, np.ndarray]:
    """(shaft, housing) diametral interference in mm of each sample (> 0 tight): shaft diameter minus ring
    bore, ring OD minus housing bore; a fit that is not sampled takes the bearing's nominal value."""
    mounting = bearing.mounting
    n = len(next(iter(samples.values()))) if samples else 0
    if "shaft_diameter_deviation" in samples:
        shaft = samples["shaft_diameter_deviation"] - samples["bore_deviation"]
    else:
        shaft = np.full(n, mounting.shaft_interference if mounting.given else 0.0)
    if "outer_diameter_deviation" in samples:
        housing = samples["outer_diameter_deviation"] - samples["housing_bore_deviation"]
    else:
        housing = np.full(n, mounting.housing_interference if mounting.given else 0.0)
    return shaft, housing


@dataclass(frozen=True)
class ClearanceBudget:
    """One row's operating clearance as a function of the two fits' nominal interferences and the unmounted
    clearance (mm), at one speed and set of temperatures: Pd_op = Pd0 - k_i p_s - k_o p_h - free, with
    p = max(I + shift, 0) / (2 compliance) each fit's pressure (N/mm^2; shift the fit's thermal and
    centrifugal change of interference, mm), k_i and k_o the raceways' diametral movement per N/mm^2 and
    ``free`` the rings' and balls' own growth (mm)."""

    shaft_shift: float
    shaft_compliance: float
    inner_per_pressure: float
    housing_shift: float
    housing_compliance: float
    outer_per_pressure: float
    free: float

    def operating_clearance(self, unmounted, shaft_interference, housing_interference):
        """Pd_op (mm) for arrays (or floats) of Pd0 and the nominal interferences (mm)."""
        p_s = np.maximum(shaft_interference + self.shaft_shift, 0.0) / (2.0 * self.shaft_compliance)
        p_h = np.maximum(housing_interference + self.housing_shift, 0.0) / (2.0 * self.housing_compliance)
        return unmounted - self.inner_per_pressure * p_s - self.outer_per_pressure * p_h - self.free


#: A probe interference (mm) that keeps both fits tight, so that the raceways' movement per pressure can be read.
_PROBE = 0.2


def clearance_budget(bearing, speed: float = 0.0) -> ClearanceBudget:
    """The :class:`ClearanceBudget` of the bearing's rows (one geometry for all) at ``speed`` rpm, from two
    evaluations of mount_row (model/mounting.py): at the nominal fits (the shifts and free growth) and at a
    tight probe fit (the raceways' compliances)."""
    mounting = bearing.mounting
    geometry = bearing.geometry
    speed = validate.number(speed, "speed", low=0.0, units="rpm")
    if not mounting.given:
        return ClearanceBudget(0.0, 1.0, 0.0, 0.0, 1.0, 0.0, 0.0)
    row = _mount(mounting, geometry, speed, warn=False)
    probe = _mount(replace(mounting, shaft_interference=_PROBE, housing_interference=_PROBE), geometry, speed,
                   warn=False)
    fs, fh = row.shaft_fit, row.housing_fit
    free = row.inner_raceway_free_growth + row.outer_raceway_free_contraction + 2.0 * row.ball_growth
    return ClearanceBudget(fs.operating_interference - fs.nominal_interference, fs.compliance,
                           probe.inner_raceway_growth / probe.shaft_fit_pressure,
                           fh.operating_interference - fh.nominal_interference, fh.compliance,
                           probe.outer_raceway_contraction / probe.housing_fit_pressure, free)


def operating_clearances(bearing, samples: dict, speed: float = 0.0) -> np.ndarray:
    """Each sample's operating diametral clearance (n,) in mm at ``speed`` rpm (all rows alike: the rows
    share one geometry and one mounting); ``samples`` from :func:`draw`."""
    shaft, housing = interferences(bearing, samples)
    unmounted = samples.get("unmounted_diametral_clearance")
    if unmounted is None:
        unmounted = np.full(shaft.shape, bearing.geometry.diametral_clearance)
    return clearance_budget(bearing, speed).operating_clearance(unmounted, shaft, housing)
