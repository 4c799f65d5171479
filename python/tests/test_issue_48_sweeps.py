"""Issue 48, the Python package's remaining defects: a process pool forked after a run on two
threads, Ctrl-C during a Dask sweep, a sweep's input checked before any point is sent, and
the units of a sweep's variables and coordinates (`save()` after unpickling is in
test_issue_48.py)."""

from __future__ import annotations

import json
import subprocess
import sys
import textwrap
from concurrent.futures import Executor, Future

import numpy as np
import pytest

import softway
from test_softway import BAR, SCENARIOS

#: The paper's bar (Fig. 8) as a dict: a run of a few milliseconds.
BAR_SCENARIO = {"kind": "bar_impact", "time": {"h": 0.1, "t_end": 2.0}, "bar": BAR}

#: The converged wheel (`wheel.toml`, 3,432 dofs: solved on two threads) shortened to a
#: few hundred steps.
SHORT_WHEEL = {
    "rolling.turns": 0.05,
    "rolling.settle_time": 2e-4,
    "rolling.fields_per_turn": 1,
    "output.plots": False,
}


def run_python(code: str, timeout: float) -> subprocess.CompletedProcess:
    """`code` in a fresh interpreter (this one's), killed after `timeout` seconds."""
    return subprocess.run(
        [sys.executable, "-c", textwrap.dedent(code)],
        capture_output=True,
        text=True,
        timeout=timeout,
    )


def test_issue_48_a_process_pool_forked_after_a_two_thread_run_returns():
    """`softway.run` of the converged wheel on two threads, then `softway.sweep` on a
    `ProcessPoolExecutor(2)` (fork, Linux's default) in the same process: the sweep returns
    both points complete. Before, the forked workers waited forever in their first parallel
    loop (the assembly) on rayon's global pool, whose threads the parent had started and
    fork does not copy; the test's subprocess then ran into its timeout."""
    code = f"""
        import json, multiprocessing, time
        from concurrent.futures import ProcessPoolExecutor
        import softway
        sc = softway.Scenario({str(SCENARIOS / "wheel.toml")!r}).with_values(**{SHORT_WHEEL!r})
        r = softway.run(sc, progress=False, threads=2)
        ctx = multiprocessing.get_context("fork")
        t = time.monotonic()
        with ProcessPoolExecutor(2, mp_context=ctx) as pool:
            ds = softway.sweep(sc, {{"rolling.omega": [250.0, 300.0]}}, executor=pool,
                               progress=False)
        print(json.dumps({{"dofs": r.summary["dofs"], "status": list(ds["status"].values),
                          "force": [float(x) for x in ds["mean_contact_force"].values],
                          "here": r.summary["mean_contact_force"],
                          "s": time.monotonic() - t}}))
    """
    try:
        p = run_python(code, timeout=240)
    except subprocess.TimeoutExpired:
        pytest.fail("the sweep on a forked process pool did not return in 240 s (hung)")
    assert p.returncode == 0, p.stderr
    out = json.loads(p.stdout.strip().splitlines()[-1])
    assert out["dofs"] >= 1500  # solved on two threads: the case that hung
    assert out["status"] == ["complete", "complete"]
    # The 300 rad/s point is the run made here (each point on one thread: the same bits).
    assert out["force"][1] == out["here"]
    assert out["force"][0] > 5e5


class CountingExecutor(Executor):
    """Runs each task at once in this process and counts them."""

    def __init__(self):
        self.submitted = 0

    def submit(self, fn, /, *args, **kwargs):
        self.submitted += 1
        f: Future = Future()
        f.set_result(fn(*args, **kwargs))
        return f


@pytest.mark.parametrize(
    "grid, key, words",
    [
        # A misspelt key: named with the keys its table takes.
        ({"bar.sped": [1.0, 2.0]}, "bar.sped", "unknown field `sped`"),
        # A value refused at the second point only.
        ({"bar.speed": [1.0, -2.0]}, "bar.speed", "`bar.speed`"),
        # A value of the wrong type.
        ({"bar.elements": [8, "many"]}, "bar.elements", "bar.elements"),
        # The same point twice.
        ({"bar.speed": [1.0, 1.0]}, "bar.speed", "given twice"),
        # The same key twice (its dotted and its keyword spelling).
        ({"bar.speed": [1.0], "bar__speed": [2.0]}, "bar.speed", "given twice"),
    ],
)
def test_issue_48_a_sweeps_keys_and_values_are_checked_before_any_point_is_sent(
    grid, key, words
):
    """Every point's values are set and validated by the engine before the executor gets
    a task: the error is the ScenarioError of the command line's `softway sweep`, its `key`
    the dotted key, and no point was sent. Before, each point failed on its own (a
    misspelt key at every point, after dispatch)."""
    ex = CountingExecutor()
    with pytest.raises(softway.ScenarioError) as e:
        softway.sweep(BAR_SCENARIO, grid, executor=ex, progress=False)
    assert e.value.key == key
    assert words in str(e.value)
    assert "\n" not in str(e.value)
    assert ex.submitted == 0
    # The same grid with good values runs every point.
    ok = softway.sweep(BAR_SCENARIO, {"bar.speed": [1.0, 2.0]}, executor=ex, progress=False)
    assert ex.submitted == 2 and list(ok["status"].values) == ["complete"] * 2


def test_issue_48_a_sweeps_history_names_are_checked_before_any_point_is_sent():
    """A misspelt `histories=` name is refused before any point runs, with the names the
    engine's history has (the run built and stopped before its first step); before, every
    point ran to its end and its results were thrown away."""
    ex = CountingExecutor()
    with pytest.raises(ValueError, match=r"'contact_force'.*contact_force_N"):
        softway.sweep(BAR_SCENARIO, {"bar.speed": [1.0, 2.0]}, executor=ex,
                      histories=["contact_force"], progress=False)
    assert ex.submitted == 0
    ds = softway.sweep(BAR_SCENARIO, {"bar.speed": [1.0, 2.0]}, executor=ex,
                       histories=["contact_force_N"], progress=False)
    assert ex.submitted == 2
    # The gathered history is each point's own run's.
    one = softway.run(BAR_SCENARIO, progress=False, **{"bar.speed": 2.0})
    f = one.history["contact_force_N"].values
    assert np.array_equal(ds["contact_force_N"].values[1, : len(f)], f)
    assert ds["contact_force_N"].attrs["units"] == "N"


def test_issue_48_a_sweeps_coordinates_and_numbers_carry_their_units():
    """The grid's coordinates carry the unit of `softway sweep`'s key column (bar.speed in
    m/s; a count such as bar.elements "1"), and the summaries' numbers the unit of their
    column in `sweep.csv` or the one their name ends with. Before, the coordinates had none
    and most numbers none (looked up by name in a table keyed by category)."""
    ds = softway.sweep(BAR_SCENARIO, {"bar.speed": [0.5, 1.0], "bar.elements": [8, 16]},
                       executor="serial", progress=False)
    assert ds["bar.speed"].attrs["units"] == "m/s"
    assert ds["bar.elements"].attrs["units"] == "1"
    for name, unit in {
        "impact_time": "s",
        "peak_contact_force": "N",
        "energy_initial": "J",
        "rebound_velocity": "m/s",
        "max_penetration": "m",
    }.items():
        assert ds[name].attrs["units"] == unit, name
    # The initial energy m v^2 / 2 (m = 1 kg) in the unit said.
    assert np.allclose(ds["energy_initial"].values[:, 0], [0.125, 0.5])
    # A growth study's speed is m/s, not s (its name ends in "_s").
    from softway._grow_sweep import _unit

    assert _unit("speed_m_s") == "m/s"
    assert _unit("wall_s") == "s"
    assert _unit("contact_stiffness_n_m") == "N/m"
    assert _unit("rate_db_per_1e5") == "dB per 1e5 real passes"


def test_issue_48_ctrl_c_during_a_dask_sweep_stops_its_tasks_and_keeps_the_finished_points():
    """A sweep on two Dask workers of one quick point and three long ones (the converged
    wheel over 0.02 and 3 turns): Ctrl-C (SIGINT to the process that called it) once the
    quick point is back and two long ones run raises SweepInterrupted within seconds. Its
    dataset has the quick point complete with its numbers, the two running points
    interrupted with what they computed (told to stop at their next step), the one not
    started interrupted without numbers; and the workers run nothing any more. Before, the
    KeyboardInterrupt left the tasks running and lost the finished point."""
    code = f"""
        import json, os, signal, threading, time
        from dask.distributed import Client, LocalCluster
        import softway
        sc = softway.Scenario({str(SCENARIOS / "wheel.toml")!r}).with_values(**{SHORT_WHEEL!r})
        cluster = LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                               dashboard_address=":0")
        client = Client(cluster)
        client.run(lambda: None)

        def states(dask_scheduler):
            return [ts.state for ts in dask_scheduler.tasks.values()]

        def interrupt():
            while True:
                s = client.run_on_scheduler(states)
                if s.count("memory") >= 1 and s.count("processing") >= 2:
                    time.sleep(1.0)
                    break
                time.sleep(0.1)
            fired["t"] = time.monotonic()
            os.kill(os.getpid(), signal.SIGINT)

        fired = {{}}
        threading.Thread(target=interrupt, daemon=True).start()
        try:
            softway.sweep(sc, {{"rolling.turns": [0.02, 3.0, 3.0001, 3.0002]}},
                          executor=client.get_executor(), mode="product", progress=False)
            out = {{"raised": None}}
        except softway.SweepInterrupted as e:
            ds = e.dataset
            after = time.monotonic() - fired["t"]
            # The workers run nothing left from the sweep.
            time.sleep(1.0)
            busy = sum(len(v) for v in client.processing().values())
            out = {{"raised": "SweepInterrupted", "after_s": after, "busy": busy,
                   "status": [str(x) for x in ds["status"].values],
                   "summaries": [json.loads(x) if x else None
                                 for x in ds["summary_json"].values],
                   "force": [float(x) for x in ds["mean_contact_force"].values]}}
        client.close()
        cluster.close()
        print(json.dumps(out))
    """
    p = run_python(code, timeout=300)
    assert p.returncode == 0, p.stderr[-3000:]
    out = json.loads(p.stdout.strip().splitlines()[-1])
    assert out["raised"] == "SweepInterrupted", out
    assert out["after_s"] < 20, out
    assert out["busy"] == 0, out
    st, sums = out["status"], out["summaries"]
    assert st[0] == "complete" and out["force"][0] > 5e5
    assert st[1:] == ["interrupted"] * 3, st
    # The two points that ran were stopped at a step: their summaries say so, their turns
    # fewer than the 3 asked for.
    ran = [s for s in sums[1:] if s is not None]
    assert len(ran) == 2, sums
    for s in ran:
        assert s["interrupted"] is True
    assert all(np.isnan(out["force"][1:]))


def test_issue_48_ctrl_c_during_a_serial_sweep_keeps_the_finished_points(monkeypatch):
    """executor="serial": Ctrl-C (KeyboardInterrupt in this thread) while the second of
    three points runs stops that run at its next step and the sweep with it:
    SweepInterrupted, its dataset the first point complete, the second interrupted with the
    steps it computed (its summary says so), the third not run. Before, the stopped point
    was recorded as failed and the sweep went on to the next point."""
    import _thread
    import threading
    import time

    from softway import _sweep

    done = []
    real = _sweep.run_point

    def counted(*args, **kwargs):
        out = real(*args, **kwargs)
        done.append(out)
        return out

    monkeypatch.setattr(_sweep, "run_point", counted)

    def interrupt():
        while not done:
            time.sleep(0.05)
        time.sleep(1.5)  # the second point is running (its model built, steps under way)
        _thread.interrupt_main()

    sc = softway.Scenario(SCENARIOS / "wheel.toml").with_values(**SHORT_WHEEL)
    threading.Thread(target=interrupt, daemon=True).start()
    with pytest.raises(softway.SweepInterrupted) as e:
        softway.sweep(sc, {"rolling.turns": [0.02, 3.0, 3.0001]}, executor="serial",
                      progress=False)
    ds = e.value.dataset
    assert list(ds["status"].values) == ["complete", "interrupted", "interrupted"]
    assert ds["mean_contact_force"].values[0] > 5e5
    assert np.isnan(ds["mean_contact_force"].values[1:]).all()
    second = json.loads(ds["summary_json"].values[1])
    assert second["interrupted"] is True and second["steps"] > 0
    assert ds["summary_json"].values[2] == ""
    assert len(done) == 2  # the third point never started


def test_issue_48_a_sweeps_out_folder_keeps_the_command_lines_folder_rules(tmp_path):
    """`sweep(out=)` claims its folder as `softway sweep` does, before any point runs: a
    folder of the user's own files is refused (nothing run, nothing written) unless
    `force=True`; a folder of `softway run`'s results is refused likewise (its marker names
    the command); a sweep's own older folder is replaced whole. Before, it wrote into any
    folder beside the user's files."""
    mine = tmp_path / "mine"
    mine.mkdir()
    (mine / "notes.txt").write_text("my own notes")
    grid = {"bar.elements": [8, 16]}
    with pytest.raises(softway.RunError, match="force"):
        softway.sweep(BAR_SCENARIO, grid, executor="serial", out=mine, progress=False)
    assert sorted(p.name for p in mine.iterdir()) == ["notes.txt"]
    ds = softway.sweep(
        BAR_SCENARIO, grid, executor="serial", out=mine, force=True, progress=False
    )
    assert list(ds["status"].values) == ["complete", "complete"]
    names = sorted(p.name for p in mine.iterdir())
    assert "notes.txt" not in names and "sweep.nc" in names, names
    assert "command: sweep" in (mine / ".softway").read_text()
    # Replaced whole by a sweep again, without force.
    softway.sweep(BAR_SCENARIO, grid, executor="serial", out=mine, progress=False)
    # A run's folder is not a sweep's.
    ran = tmp_path / "ran"
    softway.run(BAR_SCENARIO, progress=False).save(ran)
    assert "command: run" in (ran / ".softway").read_text()
    with pytest.raises(softway.RunError, match="softway run"):
        softway.sweep(BAR_SCENARIO, grid, executor="serial", out=ran, progress=False)
