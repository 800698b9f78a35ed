"""Explorers that keep their figure show what a freshly built one shows.

The gauge, level-estimation and noise-bounds explorers build their figure once and then
update its artists. The static site renders every state on one kept figure, so after any
sequence of changes the kept figure must hold the same data, titles, labels and limits as
a figure built for that state alone; an invalid setting must leave it as it was. The
gauge's faster synthesis and detection must give the numbers they gave before (stored in
tests/data/gauge_golden.npz by the code before the change).
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path
from typing import Any

import matplotlib
import numpy as np
import pytest
from golden_inputs import ULPS, nudged, shifted

matplotlib.use("Agg")

from matplotlib.figure import Figure  # noqa: E402
from matplotlib.text import Text  # noqa: E402

from dstoolkit.errors import InconsistentDataError  # noqa: E402
from dstoolkit.filters import BoundedErrorFilter, BoundedNoise  # noqa: E402
from dstoolkit.gauge import (  # noqa: E402
    PAPER_SWEEP,
    RecordingConditions,
    TubeSetup,
    detect_resonances,
    spl_to_pa,
    synthesize_recording,
    typical_conditions,
    virtual_tube_signal,
)
from dstoolkit.gauge._gauge_model import gauge_state_space_model  # noqa: E402
from dstoolkit.studies import (  # noqa: E402
    bounded_error_failures,
    noise_mismatch,
    scaled_noise,
    tracking_data,
)
from dstoolkit.teaching import (  # noqa: E402
    GAUGE_CONDITIONS,
    gauge_explorer,
    level_estimation_explorer,
    noise_bounds_explorer,
)

GOLDEN = Path(__file__).parent / "data" / "gauge_golden.npz"


def picture(fig: Figure) -> list[Any]:
    """Return what a figure shows, artist by artist: data, titles, labels, limits, legends."""
    out: list[Any] = [fig.get_size_inches().tolist()]
    for ax in fig.axes:
        out.append(
            (
                ax.get_xlim(),
                ax.get_ylim(),
                ax.get_xscale(),
                ax.get_yscale(),
                [ax.get_title(loc) for loc in ("left", "center", "right")],
                ax.get_xlabel(),
                ax.get_ylabel(),
            )
        )
        out += [
            (
                line.get_label(),
                np.asarray(line.get_xdata(), float).tolist(),
                np.asarray(line.get_ydata(), float).tolist(),
            )
            for line in ax.lines
        ]
        out += [[path.vertices.tolist() for path in c.get_paths()] for c in ax.collections]
        out += [
            [a.get_animated() for a in (*ax.lines, *ax.collections)],
            [
                (t.get_text(), t.get_fontsize(), t.get_animated())  # titles, texts
                for t in ax.get_children()
                if isinstance(t, Text)
            ],
        ]
        legend = ax.get_legend()
        out.append([t.get_text() for t in legend.get_texts()] if legend else None)
    out.append([[t.get_text() for t in legend.get_texts()] for legend in fig.legends])
    return out


def change(ex: Any, *steps: tuple[str, Any]) -> None:
    """Move the explorer's controls in turn, every setting valid."""
    for name, value in steps:
        ex.controls[name].value = value
        assert "error" not in ex.numbers, (name, value, ex.numbers)


def test_the_gauge_explorer_after_changes_shows_what_a_fresh_one_shows() -> None:
    ex = gauge_explorer()
    kept = ex.figure
    change(
        ex,
        ("level", 4.0),
        ("temperature", 20.0),
        ("top_reflection", 0.5),
        ("background", 60.0),
        ("level", 6.3),
    )
    assert ex.figure is kept
    fresh = gauge_explorer(6.3, 20.0, 0.5, 60.0)
    assert fresh.figure is not kept
    assert picture(kept) == picture(fresh.figure)
    assert ex.numbers == fresh.numbers


def test_an_invalid_gauge_setting_warns_and_keeps_the_last_figure() -> None:
    ex = gauge_explorer()
    change(ex, ("level", 1.0), ("background", 90.0))
    shown, before = ex.output.outputs, picture(ex.figure)
    ex.controls["top_reflection"].value = 0.9  # the first echo clips the converter
    assert "clipping" in ex.numbers["error"]
    assert "⚠" in ex.readout.value and "last valid setting" in ex.readout.value
    assert ex.output.outputs == shown and picture(ex.figure) == before
    change(ex, ("top_reflection", 0.4))
    assert picture(ex.figure) == picture(gauge_explorer(1.0, 26.5, 0.4, 90.0).figure)


@pytest.mark.slow
def test_the_level_explorer_keeps_one_figure_per_kind_and_shows_what_a_fresh_one_shows() -> None:
    ex = level_estimation_explorer()
    levels = ex.figure
    change(ex, ("level", 4.0), ("figure", "Fig. 10: frequencies"), ("seed", 3))
    frequencies = ex.figure
    assert frequencies is not levels
    change(ex, ("order_rule", "true"), ("figure", "Fig. 11: levels"), ("level", 6.0))
    assert ex.figure is levels
    fresh = level_estimation_explorer(6.0, 26.5, "frequency", "true", "Fig. 11: levels", 3)
    assert picture(levels) == picture(fresh.figure)
    change(ex, ("figure", "Fig. 10: frequencies"))
    assert ex.figure is frequencies
    fresh = level_estimation_explorer(6.0, 26.5, "frequency", "true", "Fig. 10: frequencies", 3)
    assert picture(frequencies) == picture(fresh.figure)
    assert ex.numbers == fresh.numbers


def test_the_noise_bounds_explorer_after_changes_shows_what_a_fresh_figure_shows() -> None:
    from dstoolkit.plots._studies import noise_bounds_figure

    ex = noise_bounds_explorer(runs=4)
    kept = ex.figure
    change(
        ex,
        ("w_upper", -3.0),
        ("v_upper", 0.4),
        ("w_lower", -11.0),
        ("start", "observation"),
        ("w_upper", -2.0),
    )
    shown, before = ex.output.outputs, picture(kept)
    ex.controls["v_mode"].value = -0.5  # below v lower: no such noise
    assert "error" in ex.numbers and "⚠" in ex.readout.value
    assert ex.output.outputs == shown and picture(ex.figure) == before
    change(ex, ("v_mode", 0.1))
    assert ex.figure is kept
    data = tracking_data(runs=4)
    v = ex.values()
    assumed_v = BoundedNoise(v["v_lower"], v["v_mode"], v["v_upper"])
    assumed_w = BoundedNoise(v["w_lower"], v["w_mode"], v["w_upper"])
    result = noise_mismatch(data, assumed_v, assumed_w, start="observation")
    fresh = noise_bounds_figure(
        data.state_noise,
        data.obs_noise,
        assumed_v,
        assumed_w,
        result.errors,
        title="L = 4.6 m, 4 runs, true orders",
        v_range=(-1.0, 1.0),
        w_range=(-20.0, 5.0),
    )
    assert picture(kept) == picture(fresh)


@pytest.mark.parametrize("scale", [0.3, 0.8, 1.0])
def test_strict_failures_from_the_batch_equal_strict_runs_one_by_one(scale: float) -> None:
    data = tracking_data(runs=12)
    model = gauge_state_space_model(
        scaled_noise(data.state_noise, scale), scaled_noise(data.obs_noise, scale)
    )
    failed, first = 0, ""
    for z, u in zip(data.readings, data.orders, strict=True):
        try:
            BoundedErrorFilter(on_inconsistent="raise").run(model, z, inputs=u)
        except InconsistentDataError as exc:
            failed, first = failed + 1, first or str(exc)
    assert bounded_error_failures(model, data) == (failed / 12, first)


def test_the_batch_result_of_the_bounded_error_filter_equals_single_runs() -> None:
    data = tracking_data(runs=20)
    model = gauge_state_space_model(
        scaled_noise(data.state_noise, 0.8), scaled_noise(data.obs_noise, 0.8)
    )
    flt = BoundedErrorFilter(on_inconsistent="reset")
    batch = flt.run_batch(model, data.readings, inputs=data.orders)
    assert 0 < np.any(batch.diagnostics["resets"], axis=1).sum() < 20  # some runs restart
    for r in range(20):
        one = flt.run(model, data.readings[r], inputs=data.orders[r])
        np.testing.assert_array_equal(batch.estimates[r], one.estimates)
        np.testing.assert_array_equal(batch.lower[r], one.lower)
        np.testing.assert_array_equal(batch.diagnostics["resets"][r], one.diagnostics["resets"])


#: The recordings stored in tests/data/gauge_golden.npz (by the synthesis before its speed-up).
GOLDEN_CASES = {
    0: (TubeSetup(4.6, 26.5), GAUGE_CONDITIONS, 0),
    1: (
        TubeSetup(1.6, 5.0, top_reflection=0.9),
        replace(GAUGE_CONDITIONS, background_noise_pa=spl_to_pa(90.0)),
        1,
    ),
    4: (
        TubeSetup(6.0, 10.0, top_reflection=0.5),
        replace(GAUGE_CONDITIONS, background_noise_pa=spl_to_pa(60.0)),
        0,
    ),
}


#: One step of the recordings' 16-bit samples (full scale ±1).
STEP_16 = 2.0**-15


def assert_like_stored_recording(case: int, setup: TubeSetup) -> None:
    """Synthesis and detection of a stored case give its stored numbers, within tolerances.

    Samples: another CPU's ``sin``/``exp`` may put an analogue value on the other side of a
    16-bit step; so at most one step, in at most 0.1 % of the stored samples. Detection:
    when the samples agree exactly (this CPU and every one seen so far), the resonances
    agree to 1e-9 Hz and the envelope to 1e-12 (relative: scipy's FFT may round its sums
    differently); one step flipped in 0.1 % of the samples moves the resonances by up to
    2.3e-5 Hz (measured on these cases), so then they must agree to 1e-4 Hz.
    """
    golden = np.load(GOLDEN)
    _, conditions, seed = GOLDEN_CASES[case]
    for _ in range(2):  # the second recording reuses the kept noise draws
        rec = synthesize_recording(setup, PAPER_SWEEP, conditions, seed=seed)
        stored = golden[f"samples{case}"]
        moved = np.abs(rec.samples[::101] - stored)
        assert moved.max() <= STEP_16 and np.count_nonzero(moved) <= stored.size // 1000
    det = detect_resonances(rec)
    assert det.latency_s == golden[f"latency{case}"]
    exact = not moved.any()
    np.testing.assert_allclose(
        det.frequencies, golden[f"frequencies{case}"], rtol=0, atol=1e-9 if exact else 1e-4
    )
    np.testing.assert_allclose(
        det.envelope[::7], golden[f"envelope{case}"], rtol=1e-12 if exact else 1e-5
    )


@pytest.mark.parametrize("case", sorted(GOLDEN_CASES))
def test_the_gauge_synthesis_and_detection_give_the_stored_numbers(case: int) -> None:
    assert_like_stored_recording(case, GOLDEN_CASES[case][0])


@pytest.mark.parametrize("case", sorted(GOLDEN_CASES))
def test_a_level_and_temperature_moved_by_a_few_ulps_give_the_stored_numbers(case: int) -> None:
    """The tube's level and temperature moved by ±4 ulp (another CPU's rounding upstream)."""
    setup = GOLDEN_CASES[case][0]
    level, temperature = shifted(setup.level_m, ULPS), shifted(setup.temperature_c, -ULPS)
    assert_like_stored_recording(
        case, replace(setup, level_m=float(level), temperature_c=float(temperature))
    )


def test_a_generator_seed_and_an_integer_seed_draw_the_same_noise() -> None:
    setup, conditions = TubeSetup(3.0, 20.0), typical_conditions()
    by_int = synthesize_recording(setup, PAPER_SWEEP, conditions, seed=5)
    by_generator = synthesize_recording(
        setup, PAPER_SWEEP, conditions, seed=np.random.default_rng(5)
    )
    np.testing.assert_array_equal(by_int.samples, by_generator.samples)
    quiet = synthesize_recording(setup, PAPER_SWEEP, RecordingConditions(), seed=5)
    assert not np.array_equal(quiet.samples, by_int.samples)


#: Tolerance of the virtual tube's signal (amplitude 0.5) against the stored one: the level
#: and temperature moved by ±4 ulp move it by 1.6e-13 (measured; the test below), and
#: another CPU's ``sin``/``exp`` by a few ulps per echo; 1e-11 leaves a margin of 60 and is
#: far below a 16-bit step (3e-5).
VIRTUAL_TUBE_ATOL = 1e-11


@pytest.mark.parametrize("seed", [None, 0, 1])
def test_the_virtual_tube_gives_the_stored_signal(seed: int | None) -> None:
    """The stored virtual-tube signal; with seed, from a level and temperature moved ±4 ulp."""
    level, temperature = 3.0, 20.0
    if seed is not None:
        level, temperature = (float(v) for v in nudged(np.array([level, temperature]), seed))
    np.testing.assert_allclose(
        virtual_tube_signal(
            TubeSetup(level, temperature), PAPER_SWEEP, conditions=typical_conditions(), seed=2
        )[::101],
        np.load(GOLDEN)["virtual_tube"],
        rtol=0,
        atol=VIRTUAL_TUBE_ATOL,
    )


def pixels(png: bytes) -> np.ndarray:
    from io import BytesIO

    from matplotlib.image import imread

    return imread(BytesIO(png))


@pytest.mark.parametrize(
    ("build", "steps", "blitted"),
    [
        (gauge_explorer, (("temperature", 20.0), ("background", 60.0)), 2),
        (level_estimation_explorer, (("temperature", 20.0), ("temperature", 26.0)), 1),
        (noise_bounds_explorer, (("w_upper", -3.0), ("v_upper", 0.4), ("w_lower", -11.0)), 3),
    ],
)
def test_a_kept_figure_redraws_only_its_data_and_shows_the_pixels_of_a_whole_draw(
    build: Any, steps: tuple[tuple[str, Any], ...], blitted: int, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Changes that move no limit redraw only the animated data and title (blitting).

    The picture shown is pixel for pixel the figure drawn whole.
    """
    from base64 import b64decode

    from dstoolkit.teaching import Explorer

    ex = build()
    draws: list[Figure] = []
    whole = Explorer._draw
    monkeypatch.setattr(Explorer, "_draw", lambda self, fig: (draws.append(fig), whole(self, fig)))
    change(ex, *steps)
    assert len(steps) - len(draws) >= blitted
    shown = pixels(b64decode(ex.output.outputs[-1]["data"]["image/png"]))
    before = len(draws)
    ex.figure.stale = True  # the next PNG is a whole draw
    np.testing.assert_array_equal(shown, pixels(ex.png(ex.figure)))
    assert len(draws) == before + 1


@pytest.mark.parametrize(
    ("data", "kwargs", "limits"),
    [
        ((0.0, 0.273), {"margin": 0.0}, (0.0, 0.3)),
        ((0.0, 0.43), {"margin": 0.0}, (0.0, 0.5)),
        ((4.1, 5.3), {"margin": 0.0}, (4.0, 5.5)),
        ((0.0, 2.6), {}, (-0.15, 3.15)),
        ((1.0, 39.0), {}, (-2.0, 42.0)),
        ((0.18, 1.4), {"log": True, "margin": 0.0}, (0.1, 2.0)),
        ((0.0005, 0.7), {"log": True, "margin": 0.0}, (0.0005, 1.0)),
    ],
)
def test_snapped_limits_reach_out_to_round_numbers(
    data: tuple[float, float], kwargs: dict[str, Any], limits: tuple[float, float]
) -> None:
    from dstoolkit.plots._kept import snapped_limits

    np.testing.assert_allclose(snapped_limits(*data, **kwargs), limits, rtol=1e-12)


def test_zero_based_limits_move_only_past_one_two_five() -> None:
    from dstoolkit.plots._kept import zero_based_limits

    assert zero_based_limits(0.0, 3.1, margin=0.0) == (0.0, 5.0)
    assert zero_based_limits(0.3, 4.9, margin=0.0) == (0.0, 5.0)
    assert zero_based_limits(0.0, 5.1, margin=0.0) == (0.0, 10.0)
    assert zero_based_limits(-0.3, 2.5, margin=0.0) == (-0.5, 5.0)
    assert zero_based_limits(-1.2, -0.1, margin=0.0) == (-2.0, 0.0)
    assert zero_based_limits(0.0, 0.0) == (-0.05, 1.05)


def test_set_limits_leaves_a_figure_clean_when_nothing_changes() -> None:
    from dstoolkit.plots._kept import set_limits

    fig = Figure()
    ax = fig.add_subplot()
    ax.set_xlim(0.0, 2.0)
    ax.set_ylim(-1.0, 1.0)
    fig.stale = False
    set_limits(ax, x=(0.0, 2.0), y=(-1.0, 1.0))
    assert not fig.stale
    set_limits(ax, y=(-1.0, 2.0))
    assert fig.stale and ax.get_ylim() == (-1.0, 2.0) and ax.get_xlim() == (0.0, 2.0)


@pytest.mark.parametrize("zoom", [None, (2.0, 2.4)])
def test_a_recording_drawn_through_its_extremes_looks_like_every_sample_drawn(
    zoom: tuple[float, float] | None,
) -> None:
    """plot_recording draws its 220,000 samples through their extremes per pixel column.

    The picture is the one of a line through every sample (no pixel off by more than 48 of
    255), the line keeps every sample, and a zoomed view draws the waves themselves.
    """
    from matplotlib.lines import Line2D

    import dstoolkit.plots._gauge as gauge_plots
    from dstoolkit.plots import plot_recording

    rec = synthesize_recording(TubeSetup(4.6, 26.5), PAPER_SWEEP, GAUGE_CONDITIONS, seed=0)
    det = detect_resonances(rec)
    pictures = []
    for line_class in (Line2D, gauge_plots.TraceLine):
        original = gauge_plots.TraceLine
        gauge_plots.TraceLine = line_class  # type: ignore[misc]
        try:
            fig = plot_recording(rec, det)
        finally:
            gauge_plots.TraceLine = original  # type: ignore[misc]
        if zoom:
            fig.axes[0].set_xlim(*zoom)
        fig.set_dpi(96)
        trace = fig.axes[0].lines[0]
        sizes: list[int] = []

        def spy(x: Any, y: Any, sizes: list[int] = sizes, set_data: Any = trace.set_data) -> None:
            sizes.append(len(x))
            set_data(x, y)

        trace.set_data = spy  # type: ignore[method-assign]
        fig.canvas.draw()
        assert type(trace) is line_class
        # the whole recording is drawn through a few thousand extremes, the zoom in full
        if line_class is not Line2D:
            assert (sizes[0] < 10_000) if zoom is None else not sizes
        np.testing.assert_array_equal(trace.get_xdata(), rec.times)
        pictures.append(np.asarray(fig.canvas.buffer_rgba()).astype(int))
    assert np.abs(pictures[0] - pictures[1]).max() <= 48


def test_a_long_trace_is_filled_in_pieces(monkeypatch: pytest.MonkeyPatch) -> None:
    """Agg fills a trace through extremes in pieces; the caller's settings are left alone.

    Agg's rasteriser keeps the cells of the largest path it filled for as long as the
    figure's canvas lives: a recording's band in one piece kept tens of MiB per figure in a
    notebook's output history.
    """
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.lines import Line2D

    import dstoolkit.plots._gauge as gauge_plots
    from dstoolkit.audio import simulate_measurement
    from dstoolkit.teaching import plot_calibration

    seen: list[tuple[int, int]] = []
    draw = Line2D.draw

    def spy(line: Line2D, renderer: Any) -> None:
        if isinstance(line, gauge_plots.TraceLine):
            seen.append((len(line.get_xdata()), matplotlib.rcParams["agg.path.chunksize"]))
        draw(line, renderer)

    monkeypatch.setattr(Line2D, "draw", spy)
    before = matplotlib.rcParams["agg.path.chunksize"]
    fig = plot_calibration(simulate_measurement(TubeSetup(level_m=2.5, temperature_c=21.0)))
    FigureCanvasAgg(fig).draw()
    # the recording (top) and the matched filter (middle), each through its extremes
    assert len(seen) == 2
    assert all(points < 10_000 and chunk == gauge_plots.TRACE_CHUNK for points, chunk in seen)
    assert matplotlib.rcParams["agg.path.chunksize"] == before
    low, high = fig.axes[0].get_ylim()
    assert low < -0.4 and high > 0.4  # fitted to the trace, whose peak is 0.5
