"""Event detection on synthetic feet with known events: clean, dragging, sinking, noisy.
Every event must be found within one frame."""

from __future__ import annotations

import numpy as np

from app.analysis import FootTracks, detect_events

FPS = 60.0
PERIOD = 1.0
SPEED = 1.2  # m/s
LAG = 0.05  # s between heel and toe (toe leaves after the heel; touches before it)


def truth(cycle: int, offset: float) -> dict[str, float]:
    """Event times of step ``cycle`` of a foot whose heel lifts at 0.45 s into its cycle."""
    start = cycle * PERIOD + offset
    return {"landing": start - 0.35 + LAG, "strike": start - 0.35, "lift": start + 0.25,
            "liftoff": start + 0.25 + LAG}


def foot_curves(t: np.ndarray, offset: float, drag: float = 0.0, sink: float = 0.0):
    """Heel, toe positions (T, 3) of a foot walking forward at SPEED; its stance is centred
    on ``offset + k``. ``drag``: seconds the foot slides along the ground before rising;
    ``sink``: how deep (m) it sinks below the ground in mid-stance."""
    n = len(t)
    heel = np.zeros((n, 3))
    toe = np.zeros((n, 3))
    for k in range(-1, int(t[-1] / PERIOD) + 2):
        ev = truth(k, offset)
        nxt = truth(k + 1, offset)
        # fore-aft: planted at the stance spot, then eased forward to the next one
        spot = (k * PERIOD + offset) * SPEED
        lift_t, land_t = ev["lift"], nxt["landing"]
        for arr, dt_up, dt_down in ((heel, 0.0, 0.0), (toe, LAG, -LAG)):
            up, down = lift_t + dt_up, land_t + dt_down
            stance = (t >= ev["landing"] + (dt_down if arr is toe else 0.0)) & (t < up)
            arr[stance, 2] = spot
            swing = (t >= up) & (t < down)
            # A dragged foot is pulled along at the body's speed, then swings forward.
            dragging = swing & (t < up + drag)
            arr[dragging, 2] = spot + SPEED * (t[dragging] - up)
            free = swing & (t >= up + drag)
            s = (t[free] - up - drag) / (down - up - drag)
            arr[free, 2] = spot + SPEED * drag + (SPEED * PERIOD - SPEED * drag) * (s * s * (3 - 2 * s))
            rise = np.clip((t[swing] - up - drag) / (down - up - drag), 0.0, 1.0)
            arr[swing, 1] = 0.08 * np.sin(np.pi * rise) * (1.0 if arr is heel else 0.7)
            if sink:
                mid = (t >= ev["landing"] + 0.1) & (t < up - 0.1)
                arr[mid, 1] -= sink * np.sin(np.pi * (t[mid] - ev["landing"] - 0.1) / (up - ev["landing"] - 0.2))
    toe[:, 0] += 0.02
    return heel, toe


def make_tracks(drag: float = 0.0, sink: float = 0.0, noise: float = 0.0) -> tuple[FootTracks, dict]:
    t = np.arange(int(5.0 * FPS)) / FPS
    offsets = {"L": 0.5, "R": 1.0}
    heels, toes = [], []
    for off in offsets.values():
        h, to = foot_curves(t, off, drag, sink)
        heels.append(h)
        toes.append(to)
    heel, toe = np.stack(heels, 1), np.stack(toes, 1)
    if noise:
        rng = np.random.default_rng(1)
        heel = heel + rng.normal(scale=noise, size=heel.shape)
        toe = toe + rng.normal(scale=noise, size=toe.shape)
    body = np.stack([np.zeros_like(t), np.full_like(t, 0.9), t * SPEED + 0.3], axis=1)
    return FootTracks(times=t, names=("L", "R"), heel=heel, toe=toe, body=body, source="synthetic",
                      hip_height=0.9), offsets


def check(tracks: FootTracks, offsets: dict, expect_lift_offset: float = 0.0) -> int:
    events = detect_events(tracks, PERIOD)
    checked = 0
    for fe in events:
        for step in fe.steps:
            if not step.complete:
                continue
            k = int(round((tracks.times[step.stance] - offsets[fe.name] + 0.05) / PERIOD))
            true = truth(k, offsets[fe.name])
            for kind in ("strike", "landing", "lift", "liftoff"):
                found = tracks.times[getattr(step, kind)]
                assert abs(found - true[kind]) <= 1.0 / FPS + 1e-9, (fe.name, k, kind, found, true[kind])
            checked += 1
    assert checked >= 6
    return checked


def test_clean_feet() -> None:
    check(*make_tracks())


def test_dragging_foot_lifts_when_it_stops_following_the_ground() -> None:
    # The foot slides forward along the ground for 0.08 s before it rises: its height says
    # "still down", its forward speed says "lifted" — the speed check wins.
    tracks, offsets = make_tracks(drag=0.08)
    events = detect_events(tracks, PERIOD)
    for fe in events:
        for step in (s for s in fe.steps if s.complete):
            k = int(round((tracks.times[step.stance] - offsets[fe.name] + 0.05) / PERIOD))
            assert abs(tracks.times[step.lift] - truth(k, offsets[fe.name])["lift"]) <= 1.0 / FPS + 1e-9


def test_foot_sinking_below_the_ground() -> None:
    check(*make_tracks(sink=0.015))


def test_noisy_feet() -> None:
    check(*make_tracks(noise=0.0004))
