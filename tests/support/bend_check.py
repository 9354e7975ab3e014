"""An independent, brute-force check of the longest rigid cylinder that passes a pipe elbow (3-D).

Nothing here comes from :mod:`pampipe.bends.geometry`: another frame, no chords, no tangent lines. The pipe
is the set of points within a = D/2 of its centreline (inlet ray along +x ending at the origin, an arc of
radius R about (0, R) turning left by θ, the outlet ray). The cylinder (diameter d) is a set of sampled
disks along its axis: each disk's rim (points ρ(cos t·n + sin t·e_z), t ∈ [0, π], and the mirror image by
symmetry) and its centre must lie in the pipe.

The cylinder must turn its axis through every direction ψ ∈ [0, θ] on its way from inlet to outlet, so the
longest one that passes is min over ψ of the longest one that fits with axis direction ψ. For each ψ the
search runs over the axis line's offset (position across the pipe) and, along each line, over the
cylinder's position (the longest run of consecutive disks that fit, ends refined by bisection).
"""

from __future__ import annotations

import numpy as np

RIM = np.linspace(0.0, np.pi, 9)  # rim angles t; z ≥ 0 suffices (the pipe is symmetric in z)


def centreline_distance(points: np.ndarray, radius: float, angle: float) -> np.ndarray:
    """Distance [m] of 3-D points (..., 3) to the centreline: inlet ray, arc, outlet ray."""
    x, y, z = points[..., 0], points[..., 1], points[..., 2]
    inlet = np.sqrt(np.where(x <= 0, 0.0, x * x) + y * y + z * z)
    qx, qy = x, y - radius
    phi = np.arctan2(qx, -qy)  # the arc point at φ is (R sin φ, R − R cos φ)
    on_arc = (phi >= 0) & (phi <= angle)
    arc = np.where(on_arc, np.sqrt((np.hypot(qx, qy) - radius) ** 2 + z * z), np.inf)
    ex, ey = radius * np.sin(angle), radius - radius * np.cos(angle)
    ux, uy = np.cos(angle), np.sin(angle)
    s = (x - ex) * ux + (y - ey) * uy
    px, py = x - ex - np.maximum(s, 0) * ux, y - ey - np.maximum(s, 0) * uy
    outlet = np.sqrt(px * px + py * py + z * z)
    return np.minimum(np.minimum(inlet, arc), outlet)


def _disks_fit(centres: np.ndarray, psi: float, rho: float, a: float, radius: float, angle: float):
    """True for each disk centre (..., 2) whose disk (normal along ψ, radius ρ) lies in the pipe."""
    n = np.array([-np.sin(psi), np.cos(psi)])
    offsets = np.zeros((RIM.size + 1, 3))
    offsets[:-1, :2] = rho * np.cos(RIM)[:, None] * n[None, :]
    offsets[:-1, 2] = rho * np.sin(RIM)
    points = np.zeros((*centres.shape[:-1], RIM.size + 1, 3))
    points[..., :2] = centres[..., None, :]
    points = points + offsets
    return np.all(centreline_distance(points, radius, angle) <= a, axis=-1)


def _longest_runs(offsets, psi, rho, a, radius, angle, span, step, steps=30):
    """Longest fitting run [m] along each line of direction ψ, one line per offset (across the pipe, at the
    arc point φ = ψ where the centreline runs parallel to the lines); ends refined by bisection."""
    u = np.array([np.cos(psi), np.sin(psi)])
    n = np.array([-np.sin(psi), np.cos(psi)])
    abeam = np.array([radius * np.sin(psi), radius - radius * np.cos(psi)])  # centreline point, tangent ∥ u
    feet = abeam[None, :] - offsets[:, None] * n[None, :]  # offset > 0: toward the outer wall
    tau = np.arange(-span, span + step, step)
    centres = feet[:, None, :] + tau[None, :, None] * u[None, None, :]
    fit = _disks_fit(centres, psi, rho, a, radius, angle)  # (lines, τ)
    edge = np.zeros((fit.shape[0], 1), bool)
    padded = np.concatenate([edge, fit, edge], axis=1)
    back = np.full(offsets.size, np.nan)
    front = np.full(offsets.size, np.nan)
    for i, row in enumerate(padded):
        edges = np.flatnonzero(np.diff(row.astype(int)))
        if edges.size:
            starts, ends = edges[::2], edges[1::2] - 1
            k = int(np.argmax(ends - starts))
            back[i], front[i] = (-np.inf if starts[k] == 0 else tau[starts[k]],
                                 np.inf if ends[k] == tau.size - 1 else tau[ends[k]])
    out = np.zeros(offsets.size)
    found = np.isfinite(back) | np.isfinite(front) | (back == -np.inf)
    ends = []
    for value, outward in ((back, -step), (front, step)):
        inside = np.where(np.isfinite(value), value, 0.0)
        outside = inside + outward
        for _ in range(steps):
            mid = 0.5 * (inside + outside)
            ok = _disks_fit(feet + mid[:, None] * u[None, :], psi, rho, a, radius, angle)
            inside, outside = np.where(ok, mid, inside), np.where(ok, outside, mid)
        ends.append(np.where(np.isfinite(value), inside, value))
    out = np.where(found & ~np.isnan(back), ends[1] - ends[0], 0.0)
    return out


def longest_at_direction(psi, *, bore, radius, angle, diameter, rounds=3, points=21):
    """max over offsets of the longest fitting cylinder with axis direction ψ [m] (zooming grid search)."""
    a, rho = bore / 2, diameter / 2
    span = 3 * radius + 8 * bore
    step = bore / 15
    low, high = -(a - rho), a - rho  # where the line crosses the section φ = ψ, from the centreline
    best = 0.0
    for _ in range(rounds):
        offsets = np.linspace(low, high, points)
        runs = _longest_runs(offsets, psi, rho, a, radius, angle, span, step)
        k = int(np.argmax(runs))
        best = max(best, runs[k])
        width = (high - low) / (points - 1)
        low, high = offsets[k] - width, offsets[k] + width
    return best


def longest_passing(*, bore, radius, angle, diameter, directions=17, rounds=3):
    """min over ψ ∈ [0, θ] of :func:`longest_at_direction` [m] (zooming grid search on ψ)."""
    if diameter >= bore:
        return 0.0
    low, high = 0.0, angle
    best = np.inf
    for _ in range(rounds):
        grid = np.linspace(low, high, directions)
        values = np.array([longest_at_direction(p, bore=bore, radius=radius, angle=angle, diameter=diameter)
                           for p in grid])
        k = int(np.argmin(values))
        best = min(best, values[k])
        width = (high - low) / (directions - 1)
        low, high = max(grid[k] - width, 0.0), min(grid[k] + width, angle)
    return best
