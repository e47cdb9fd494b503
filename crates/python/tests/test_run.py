"""Runs from Python: the same bytes as the command line, any thread count, the tables, and
interruption with a checkpoint that resumes to the same bits."""

import os
import signal
import subprocess
import sys
import textwrap
import time

import numpy as np
import pytest

import hopperflow as hf
from conftest import TINY
from hopperflow._testing import numpy_tables


def test_summary_is_byte_identical_to_the_cli(cli_run, py_run):
    # Determinism is the contract: the Python module runs the same code on the same case.
    assert (py_run.path / "summary.json").read_bytes() == (cli_run / "summary.json").read_bytes()
    for name in ["flow.csv", "wall_forces.csv", "profiles.csv", "field.csv", "case.toml"]:
        assert (py_run.path / name).read_bytes() == (cli_run / name).read_bytes(), name


def test_two_threads_give_the_same_bits(py_run, tmp_path):
    two = hf.run(str(TINY), out=tmp_path / "two", threads=2, progress=False)
    assert (two.path / "summary.json").read_bytes() == (py_run.path / "summary.json").read_bytes()


def test_summary_and_tables(py_run):
    summary = py_run.summary
    # The tiny hopper discharges: a positive rate with an error smaller than itself.
    assert summary["discharge_rate"] > 0
    assert 0 <= summary["discharge_rate_error"] < summary["discharge_rate"]
    flow = py_run.flow
    assert list(flow.columns) == ["time", "rate", "cumulative_mass"]
    # The cumulative mass never decreases.
    assert np.all(np.diff(flow["cumulative_mass"].to_numpy()) >= 0)
    assert len(py_run.profiles) > 0 and len(py_run.field) > 0


def test_tables_are_numpy_dicts_without_pandas(py_run):
    with numpy_tables():
        flow = py_run.flow
    assert isinstance(flow, dict) and flow["time"].dtype == np.float64
    # The same bits as the CSV text: Python's float() reads the writer's shortest digits.
    first = (py_run.path / "flow.csv").read_text().splitlines()[1].split(",")
    assert flow["rate"][0] == float(first[1])


def test_crossings_are_a_table_and_absent_tables_raise_file_not_found(py_run):
    crossings = py_run.crossings
    times = np.asarray(crossings["time_s"])
    # Every crossing of the outlet line, in time order, each one downward.
    assert len(times) > 0
    assert np.all(np.diff(times) >= 0)
    assert np.all(np.asarray(crossings["velocity_z_m_per_s"]) < 0)
    # Each crossing is one particle of the case.
    assert np.asarray(crossings["id"]).max() < 250
    with pytest.raises(FileNotFoundError, match="no_such.csv"):
        py_run.table("no_such.csv")
    with pytest.raises(AttributeError):
        py_run.not_a_table


def test_load_run_and_reprs(py_run, tmp_path):
    again = hf.load_run(py_run.path)
    assert again.summary == py_run.summary
    page = again._repr_html_()
    # The notebook view shows the rate and the W(t) figure inline.
    assert "discharge_rate" in page and "data:image/png;base64," in page
    assert again.case["particles.count"] == 250
    with pytest.raises(FileNotFoundError):
        hf.load_run(tmp_path)


def test_an_occupied_folder_is_refused_unless_resumed(py_run):
    with pytest.raises(FileExistsError, match="resume=True"):
        hf.run(str(TINY), out=py_run.path, progress=False)
    # resume=True reads the finished run back without running it again.
    before = (py_run.path / "summary.json").read_bytes()
    hf.run(str(TINY), out=py_run.path, progress=False, resume=True)
    assert (py_run.path / "summary.json").read_bytes() == before
    with pytest.raises(ValueError, match="exclude each other"):
        hf.run(str(TINY), out=py_run.path, progress=False, resume=True, restart=True)


def test_resume_of_other_inputs_is_refused(py_run):
    case = hf.Case.load(str(TINY))
    case["seed"] = 12
    with pytest.raises(ValueError, match="seed"):
        hf.run(case, out=py_run.path, progress=False, resume=True)


@pytest.mark.parametrize("threads, error", [(0, ValueError), (-1, ValueError), (10**6, ValueError), ("2", TypeError)])
def test_bad_thread_counts(threads, error, tmp_path):
    with pytest.raises(error, match="threads"):
        hf.run(str(TINY), out=tmp_path / "t", threads=threads, progress=False)
    # Nothing was written for refused arguments.
    assert not (tmp_path / "t").exists()


def test_estimate_bounds_the_tiny_run_and_reckons_its_discharge_by_beverloo(tmp_path):
    e = hf.estimate(hf.Case.load(str(TINY)))
    assert e["particles"] == 250 and e["refusal"] is None
    # hf.estimate always times the engine (the command line skips it for short runs only).
    assert e["speed"] is not None and e["speed"]["ns_per_particle_step"] > 0
    d = e["likely"]["discharge"]
    # The slot's 2D Beverloo law at D = 18 mm with C = 0.58, k = 1.55, ρ_b = 1475 kg/m³:
    # 12.5 g/s (docs/physics.md §8.2, which rounds it to 0.1 g/s).
    assert d["law"] == "beverloo_2d"
    assert abs(d["rate"] - 0.0125) < 1e-4
    # The 8.8 g fill would take 0.71 s to leave, past the 0.6 s limit: the likely discharge
    # is the bound, never more (equal up to the rounding of a sum, 1e-12 s).
    assert d["flowing"] > 0.6
    assert abs(e["likely"]["simulated"]["discharge"] - e["simulated"]["discharge"]) < 1e-12
    # The likely wall time is never over the bound; an estimate writes nothing.
    assert e["likely_wall_time_total_s"] <= e["wall_time_total_s"]
    assert list(tmp_path.iterdir()) == []


def test_bad_case_argument(tmp_path):
    with pytest.raises(TypeError, match="case"):
        hf.run(42, out=tmp_path / "x", progress=False)  # type: ignore[arg-type]  # the misuse tested


def test_an_interrupt_leaves_a_checkpoint_that_resumes_to_the_same_bits(cli_run, tmp_path):
    # A progress callback that raises KeyboardInterrupt takes the path Ctrl-C takes
    # (the interrupt arrives between two looks at the run), at a point that does not
    # depend on timing.
    out = tmp_path / "stopped"
    calls = []

    def stop_soon(progress: hf.RunProgress) -> None:
        calls.append(progress)
        if len(calls) == 3:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        hf.run(str(TINY), out=out, progress=stop_soon)
    assert (out / "checkpoint.bin").is_file() and not (out / "summary.json").exists()
    # The callable got one RunProgress per report, fields and line alike.
    first = calls[0]
    assert isinstance(first, hf.RunProgress) and first.phase in {"fill", "settle", "discharge"}
    assert 0 <= first.fraction <= 1 and first.time > 0 and first.particles >= 0
    assert first.message.startswith(f"{first.phase} t = ")
    hf.run(str(TINY), out=out, progress=False, resume=True)
    assert (out / "summary.json").read_bytes() == (cli_run / "summary.json").read_bytes()


def test_ctrl_c_stops_a_run_with_a_checkpoint(tmp_path):
    # A real SIGINT to a Python process running the paper's base case (minutes long): it
    # must stop within seconds, raise KeyboardInterrupt and leave a checkpoint.
    out = tmp_path / "base"
    # The child installs Python's own SIGINT handler: a test command started in the
    # background (nohup, `cmd &` in a script, some CI runners) passes SIGINT on as ignored,
    # and Python then leaves it ignored, so the run would go on to its end.
    script = textwrap.dedent(
        f"""
        import signal, sys, hopperflow as hf
        signal.signal(signal.SIGINT, signal.default_int_handler)
        started = []
        def progress(p):
            if not started:
                started.append(1)
                print("running", flush=True)
        try:
            hf.run(hf.Case.paper(), out={str(out)!r}, progress=progress)
        except KeyboardInterrupt:
            print("interrupted", flush=True)
            sys.exit(0)
        print("finished", flush=True)
        """
    )
    proc = subprocess.Popen([sys.executable, "-c", script], stdout=subprocess.PIPE, text=True)
    assert proc.stdout is not None
    try:
        assert proc.stdout.readline().strip() == "running"
        sent = time.monotonic()
        proc.send_signal(signal.SIGINT)
        rest, _ = proc.communicate(timeout=60)
    finally:
        if proc.poll() is None:
            proc.kill()
    # A protocol chunk takes milliseconds; 10 s allows for a slow, shared machine.
    assert time.monotonic() - sent < 10
    assert rest.strip() == "interrupted" and proc.returncode == 0
    assert (out / "checkpoint.bin").is_file() and not (out / "summary.json").exists()


def test_the_gil_is_released_during_a_run(tmp_path):
    # A Python thread keeps counting while a run goes on in another: with the GIL held by
    # the run, it could not count at all until the run ended.
    import threading

    counts = []
    done = threading.Event()

    def count():
        n = 0
        while not done.is_set():
            n += 1
            if n % 1000 == 0:
                counts.append(time.monotonic())

    worker = threading.Thread(target=count)
    worker.start()
    started = time.monotonic()
    try:
        hf.run(str(TINY), out=tmp_path / "gil", progress=False)
    finally:
        ended = time.monotonic()
        done.set()
        worker.join()
    during = [t for t in counts if started < t < ended]
    assert len(during) > 100, "the counting thread starved while the run held the GIL"


# Gravity of the runs [m/s²] (the engine's, along −z).
G = 9.81

WALL_FORCE_COLUMNS = ["time", "wall", "fx", "fy", "fz", "tx", "ty", "tz"]


def bed_weight(case):
    """m g of the tiny case's fill [N]: monodisperse spheres of the case's density."""
    d = case["particles.diameter"]
    return case["particles.count"] * case["particles.material.density"] * np.pi * d**3 / 6 * G


def test_wall_forces_before_the_opening_carry_the_settled_bed(py_run):
    forces = py_run.wall_forces
    assert list(forces.columns) == WALL_FORCE_COLUMNS
    assert forces["time"].dtype == np.float64 and forces["fz"].dtype == np.float64
    summary, case = py_run.summary, py_run.case
    opened = summary["fill_time"]
    times = forces["time"].to_numpy()
    walls = forces["wall"].to_numpy()
    # Windows through the whole run (time [s] from its start), never past its end; the
    # faces, whose load is not summed, have no rows; the gate none after it opened.
    assert times.min() > 0 and times.max() <= opened + summary["discharge_time"]
    assert set(walls) == {"left", "right", "plate_left", "plate_right", "gate"}
    assert np.all(times[walls == "gate"] < opened)
    assert np.any(times > opened)
    # The last window before the opening: the settled bed rests on the walls, which it
    # presses down (fz < 0, the force the particles exert [N]) with its whole weight m g.
    # The faces of the 1.01 d slab take a little of it by friction; measured, the walls
    # that sum their load carry 0.9978 m g, and 1 % is the margin.
    last = forces[times == times[times < opened].max()]
    weight = bed_weight(case)
    total = last["fz"].sum()
    assert abs(total + weight) < 0.01 * weight, (total, weight)
    # The gate carries the part of the bed over the outlet, of the order of its share D/L
    # of the floor (measured 1.37 D/L: the middle of this shallow bed presses harder than
    # the edges, where the side walls hold part of it by friction). Half to twice D/L.
    gate = last[last["wall"] == "gate"]["fz"].item()
    share = case["geometry.outlet_width"] / case["geometry.width"]
    assert 0.5 * share * weight < -gate < 2 * share * weight, (gate, weight)
    # Its torque about the origin [N m] puts the load's line of action over the outlet:
    # for a floor in z = 0, τ_y = −x F_z.
    x = -last[last["wall"] == "gate"]["ty"].item() / gate
    assert abs(x) < case["geometry.outlet_width"] / 2


def test_wall_forces_without_pandas_and_from_load_run(py_run):
    with numpy_tables():
        forces = hf.load_run(py_run.path).wall_forces
    assert isinstance(forces, dict) and list(forces) == WALL_FORCE_COLUMNS
    # Names as text, loads as the float64 bits of the CSV text.
    assert forces["wall"].dtype.kind == "U" and forces["fx"].dtype == np.float64
    first = (py_run.path / "wall_forces.csv").read_text().splitlines()[1].split(",")
    assert forces["wall"][0] == first[1] and forces["fz"][0] == float(first[4])


def _lattice_csv(path, material="glass"):
    """250 spheres of the tiny hopper on a square lattice 1 % wider than a diameter, 0.1 mm
    clear of the floor and the left wall: at rest and touching nothing (as the Rust packing
    tests place them)."""
    r, spacing = 1.5e-3, 3.03e-3
    lines = ["x,y,z,radius,material"]
    for k in range(250):
        x = -0.025 + r + 1e-4 + (k % 16) * spacing
        z = r + 1e-4 + (k // 16) * spacing
        lines.append(f"{x!r},{0.5 * spacing!r},{z!r},{r!r},{material}")
    path.write_text("\n".join(lines) + "\n")
    return path


def test_runs_from_a_saved_bed_and_from_a_packing_match_the_command_line(cli, tiny_bed, tmp_path):
    bed = tiny_bed
    assert (bed / "bed.bin").is_file()
    # The same bed through a wider outlet, from Python and from the command line: the same
    # summary to the byte (a run from a bed starts from its state, whatever the seed).
    case = hf.Case.load(str(TINY))
    case["geometry.outlet_width"] = 0.024
    py = hf.run(case, out=tmp_path / "py-bed", progress=False, from_bed=bed)
    subprocess.run(
        [str(cli), "run", str(TINY), "--from-bed", str(bed), "--set", "geometry.outlet_width=0.024",
         "--out", str(tmp_path / "cli-bed"), "--quiet"],
        check=True, capture_output=True,
    )
    assert (py.path / "summary.json").read_bytes() == (tmp_path / "cli-bed" / "summary.json").read_bytes()
    # Without a case the bed's own is the base, as `hopperflow run --from-bed DIR`.
    own = hf.run(out=tmp_path / "py-own", progress=False, pictures=False, from_bed=bed)
    assert own.summary["outlet_width"] == pytest.approx(0.018, abs=0.0)

    packing = _lattice_csv(tmp_path / "lattice.csv")
    py = hf.run(str(TINY), out=tmp_path / "py-packing", progress=False, packing=packing)
    subprocess.run(
        [str(cli), "run", str(TINY), "--packing", str(packing), "--out", str(tmp_path / "cli-packing"), "--quiet"],
        check=True, capture_output=True,
    )
    assert (py.path / "summary.json").read_bytes() == (tmp_path / "cli-packing" / "summary.json").read_bytes()


def test_bad_starts_are_refused_before_anything_is_written(tiny_bed, tmp_path):
    bad = tmp_path / "bad.csv"
    bad.write_text("x,y,z,radius,material\n0.0,0.0015,0.01,0.0015,glass\n0.0,0.0015,0.02,-1,glass\n")
    with pytest.raises(ValueError, match=r"bad\.csv line 3: radius = -1"):
        hf.run(str(TINY), out=tmp_path / "a", progress=False, packing=bad)
    assert not (tmp_path / "a").exists()
    with pytest.raises(ValueError, match="exclude each other"):
        hf.run(str(TINY), out=tmp_path / "b", progress=False, packing=bad, from_bed=tmp_path)
    assert not (tmp_path / "b").exists()
    with pytest.raises(ValueError, match="no saved bed there"):
        hf.run(str(TINY), out=tmp_path / "c", progress=False, from_bed=tmp_path / "nowhere")
    assert not (tmp_path / "c").exists()

    bed = tiny_bed
    # A bed holds its fill: the particle count cannot change under it.
    case = hf.Case.load(str(TINY))
    case["particles.count"] = 200
    with pytest.raises(ValueError, match=r"settled under other inputs.*particles\.count"):
        hf.run(case, out=tmp_path / "d", progress=False, from_bed=bed)
    assert not (tmp_path / "d").exists()
    # Another run may not overwrite a saved bed, unless it starts over.
    other = hf.Case.load(str(TINY))
    other["seed"] = 12
    with pytest.raises(ValueError, match="holds a saved bed already"):
        hf.run(other, out=tmp_path / "e", progress=False, save_bed=bed)
    assert not (tmp_path / "e").exists()
