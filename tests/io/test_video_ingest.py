"""``hydrokit ingest --format video`` (issue #12 item 5, ENG2009 eq. 11): videos rendered with
OpenCV (MJPG .avi) of a marker swinging on a known θ(t) — a virtual-rig pendulum decay — with
blur and noise, tracked, and identified."""

from __future__ import annotations

import json
import math
import sys
from pathlib import Path

import numpy as np
import pytest

import hydrokit
from hydrokit.identify.virtual_rig import SensorModel, simulate_launch

cv2 = pytest.importorskip("cv2")

RIG = Path(hydrokit.__file__).parent / "data" / "campaigns" / "udrobot" / "pendulum_x.yaml"
TRUE = {"added_mass": 0.06, "linear_damping": 0.05, "quadratic_damping": 1.0}
PIVOT, RADIUS, W, H = (318.4, 36.7), 383.2, 640, 480


@pytest.fixture(scope="module")
def rig():
    return hydrokit.load_rig(RIG)


def render(path: Path, theta: np.ndarray, fps: float, *, dark: bool = True, lost=(), seed: int = 0) -> None:
    """A 640×480 MJPG video: a 9 px disc (contrast 110) at RADIUS px from PIVOT at angle θ (from the
    downward vertical, + to the image right), a faint rod, Gaussian blur σ = 1.2 px, noise σ = 3."""
    fourcc = cv2.VideoWriter_fourcc(*("mp4v" if path.suffix == ".mp4" else "MJPG"))
    writer = cv2.VideoWriter(str(path), fourcc, fps, (W, H))
    assert writer.isOpened()
    cv2.setRNGSeed(seed)
    bg, sign = (165.0, -1.0) if dark else (60.0, 1.0)
    noise = np.empty((H, W), np.float32)
    r0, half = 9.0, 14
    for k, th in enumerate(theta):
        img = np.full((H, W), bg, np.float32)
        x, y = PIVOT[0] + RADIUS * math.sin(th), PIVOT[1] + RADIUS * math.cos(th)
        cv2.line(img, (round(PIVOT[0]), round(PIVOT[1])), (round(x), round(y)), bg + sign * 25.0, 2, cv2.LINE_AA)
        if k not in lost:
            i0, j0 = int(y) - half, int(x) - half
            yy, xx = np.mgrid[i0 : i0 + 2 * half + 1, j0 : j0 + 2 * half + 1]
            cover = np.clip(r0 + 0.5 - np.hypot(xx - x, yy - y), 0.0, 1.0)
            img[i0 : i0 + 2 * half + 1, j0 : j0 + 2 * half + 1] = bg + sign * 110.0 * cover
        img = cv2.GaussianBlur(img, (0, 0), 1.2)
        cv2.randn(noise, 0.0, 3.0)
        frame = np.clip(img + noise, 0, 255).astype(np.uint8)
        writer.write(cv2.cvtColor(frame, cv2.COLOR_GRAY2BGR))
    writer.release()


def _launch(rig, amp_deg: float, fps: float = 40.0, seed: int = 0, duration: float = 12.0):
    return simulate_launch(rig, *TRUE.values(), math.radians(amp_deg), duration, SensorModel(fps, hold_time=2.0), seed)


def _ingest(run_cli, src: Path, out: Path, *args):
    code, _, err = run_cli("ingest", src, "--rig", RIG, "--out", out, *args)
    assert code == 0, err
    data = np.loadtxt(out / "launch_001.csv", delimiter=",", skiprows=3)
    return data[:, 0], data[:, 1], json.loads((out / "ingest.json").read_text())


def _rms_deg(a: np.ndarray, b: np.ndarray) -> float:
    return math.degrees(float(np.sqrt(np.mean((a - b) ** 2))))


def test_video_is_tracked_and_identified(tmp_path, rig, run_cli) -> None:
    la = _launch(rig, 20.0)
    src = tmp_path / "swing.avi"
    render(src, la.y, 40.0)
    out = tmp_path / "o"
    t, y, doc = _ingest(run_cli, src, out, "--plots")
    assert doc["format"] == "video"
    assert np.allclose(t, la.t, atol=1e-6)  # the container's frame times
    err = _rms_deg(y, la.y)
    print(f"video angle RMS error {err:.4f}°")
    assert err <= 0.1
    tr = doc["tracking"]
    assert tr["pivot"]["x"] == pytest.approx(PIVOT[0], abs=1.0)
    assert tr["pivot"]["y"] == pytest.approx(PIVOT[1], abs=3.0)
    assert tr["radius_px"] == pytest.approx(RADIUS, abs=3.0)
    assert tr["lost_frames"] == 0 and tr["dropped_frames"] == 0 and tr["frames"] == la.t.size
    pf = tr["per_frame"]
    assert len(pf["area_px"]) == len(pf["contrast"]) == len(pf["circle_distance_px"]) == la.t.size
    assert (out / "ingest.png").stat().st_size > 1000 and (out / "tracking.png").stat().st_size > 1000
    ma = hydrokit.identify_campaign(rig, [str(out / "launch_001.csv")]).mean("added_mass")
    print(f"identified added mass {ma:.5f} kg (true {TRUE['added_mass']})")
    assert ma == pytest.approx(TRUE["added_mass"], rel=0.01)


def test_bright_marker_and_given_pivot(tmp_path, rig, run_cli) -> None:
    la = _launch(rig, -15.0, fps=30.0, duration=4.0)
    src = tmp_path / "bright.avi"
    render(src, la.y, 30.0, dark=False, seed=3)
    _, y, doc = _ingest(run_cli, src, tmp_path / "b", "--marker", "bright")
    assert _rms_deg(y, la.y) <= 0.1
    _, y2, doc2 = _ingest(run_cli, src, tmp_path / "p", "--marker", "bright", "--pivot", f"{PIVOT[0]},{PIVOT[1]}")
    assert doc2["tracking"]["pivot"] == {"x": PIVOT[0], "y": PIVOT[1], "from": "--pivot"}
    assert _rms_deg(y2, la.y) <= 0.1
    # --fps overrides the container's times; --roi restricts the search
    t3, y3, doc3 = _ingest(run_cli, src, tmp_path / "f", "--format", "video", "--marker", "bright", "--fps", "60",
                           "--roi", "100,250,440,230")  # fmt: skip
    assert t3[1] - t3[0] == pytest.approx(1 / 60, abs=1e-4) and doc3["tracking"]["roi"] == [100, 250, 440, 230]
    assert _rms_deg(y3, la.y) <= 0.1


def test_pure_tracker_math() -> None:
    from scipy.ndimage import gaussian_filter

    from hydrokit.io.video import blob_centroid, fit_circle

    a = np.linspace(-0.4, 0.3, 50)
    rng = np.random.default_rng(1)
    x, y = 100 + 250 * np.sin(a) + rng.normal(0, 0.05, a.size), -20 + 250 * np.cos(a) + rng.normal(0, 0.05, a.size)
    assert fit_circle(x, y) == pytest.approx((100, -20, 250), abs=0.3)
    yy, xx = np.mgrid[0:41, 0:41]
    img = gaussian_filter(200.0 - 120.0 * np.clip(6.5 - np.hypot(xx - 20.3, yy - 17.8), 0, 1), 1.2)
    cx, cy, area, contrast, _ = blob_centroid(img, dark=True)
    assert (cx, cy) == pytest.approx((20.3, 17.8), abs=0.02) and contrast == pytest.approx(120.0, rel=0.1)
    assert area == pytest.approx(math.pi * 6**2, rel=0.15)


def test_lost_marker_and_missing_extra(tmp_path, rig, run_cli, monkeypatch) -> None:
    la = _launch(rig, 15.0, fps=30.0, duration=3.0)
    few = tmp_path / "few.mp4"  # lost in 10 % of the frames: left out, with a warning
    render(few, la.y, 30.0, lost=set(range(0, la.t.size, 10)))
    t, y, doc = _ingest(run_cli, few, tmp_path / "few")
    n_lost = len(range(0, la.t.size, 10))
    assert doc["format"] == "video" and doc["tracking"]["lost_frames"] == n_lost == sum(
        doc["tracking"]["per_frame"]["lost"]
    )
    assert t.size == la.t.size - n_lost and any("marker lost in" in w for w in doc["warnings"])
    keep = ~np.asarray(doc["tracking"]["per_frame"]["lost"])
    assert _rms_deg(y, la.y[keep]) <= 0.1
    src = tmp_path / "lost.avi"
    render(src, la.y, 30.0, lost=set(range(0, la.t.size, 4)))  # 25 % of the frames
    out = tmp_path / "never"
    code, _, err = run_cli("ingest", src, "--rig", RIG, "--out", out)
    assert code == 2 and len(err.strip().splitlines()) == 1 and not out.exists()
    assert "marker lost in" in err and "> 20%" in err
    code, _, err = run_cli("ingest", src, "--rig", RIG, "--out", out, "--roi", "1,2,3")
    assert code == 2 and not out.exists()
    assert err.splitlines() == ["error: --roi '1,2,3': expected 4 numbers in pixels separated by commas"]
    junk = tmp_path / "junk.mp4"
    junk.write_bytes(b"not a video")
    code, _, err = run_cli("ingest", junk, "--rig", RIG, "--out", out)
    assert code == 2 and len(err.strip().splitlines()) == 1 and "cannot open" in err and not out.exists()
    monkeypatch.setitem(sys.modules, "cv2", None)
    code, _, err = run_cli("ingest", src, "--rig", RIG, "--out", out)
    assert code == 2 and "pip install 'hydrokit[video]'" in err and not out.exists()
