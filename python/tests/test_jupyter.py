"""softway in a real Jupyter kernel (ipykernel, driven by jupyter_client as a notebook
front end drives it): interrupting a cell that runs softway.run stops the run within a step
and raises softway.RunInterrupted carrying the partial result; the tqdm.auto progress bar
is a widget that updates while the run goes when ipywidgets is installed, and text on
stderr when it is not.

Skipped only when jupyter_client or ipykernel is missing (`.ci/run` installs both, and
ipywidgets)."""

from __future__ import annotations

import json
import queue
import sys
import time
from pathlib import Path

import pytest

jupyter_client = pytest.importorskip("jupyter_client")
pytest.importorskip("ipykernel")

from jupyter_client.manager import start_new_kernel  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
SCENARIOS = ROOT / "scenarios"


@pytest.fixture()
def kernel():
    """A fresh Python kernel of this interpreter (ipykernel's own spec, `python3`)."""
    km, kc = start_new_kernel(kernel_name="python3", startup_timeout=120)
    try:
        yield km, kc
    finally:
        kc.stop_channels()
        km.shutdown_kernel(now=True)


def execute(kc, code: str, on_message=None, timeout: float = 300.0):
    """Runs `code` in the kernel as a notebook cell; returns (the execute_reply's content,
    the iopub messages of the cell). `on_message(msg)` sees each iopub message as it
    comes (the cell still running)."""
    msg_id = kc.execute(code)
    messages = []
    deadline = time.monotonic() + timeout
    idle = False
    while not idle:
        left = deadline - time.monotonic()
        assert left > 0, f"the cell did not finish in {timeout} s: {code}"
        try:
            msg = kc.get_iopub_msg(timeout=min(left, 1.0))
        except queue.Empty:
            continue
        if msg["parent_header"].get("msg_id") != msg_id:
            continue
        messages.append(msg)
        if on_message is not None:
            on_message(msg)
        if msg["msg_type"] == "status" and msg["content"]["execution_state"] == "idle":
            idle = True
    reply = kc.get_shell_msg(timeout=timeout)
    while reply["parent_header"].get("msg_id") != msg_id:
        reply = kc.get_shell_msg(timeout=timeout)
    return reply["content"], messages


def stdout_of(messages) -> str:
    return "".join(
        m["content"]["text"]
        for m in messages
        if m["msg_type"] == "stream" and m["content"]["name"] == "stdout"
    )


def test_interrupting_a_cell_stops_the_run_within_a_step(kernel):
    """The mesh-converged wheel (scenarios/wheel.toml) rolling 40 turns (a minute or more):
    once the run is 1,000 steps into its time loop (the cell prints it from the progress
    callback), the kernel is interrupted (SIGINT, as the notebook's stop button sends it);
    the cell ends within a second with RunInterrupted, whose result holds the steps
    computed (a small part of the run), marked interrupted. (A signal during the model's
    set-up, before the steps, takes effect when they start: docs/src/python.md.)"""
    km, kc = kernel
    started = {}

    def watch(msg):
        if msg["msg_type"] == "stream" and "IN THE TIME LOOP" in msg["content"].get("text", ""):
            started.setdefault("t", time.monotonic())

    # xarray and pandas imported first, as a notebook that reads results has them: the
    # first Result of a session imports them (1-3 s on a loaded machine), which is not
    # the run's stop.
    setup = (
        "import softway, sys, xarray, pandas\n"
        f"sc = softway.Scenario({str(SCENARIOS / 'wheel.toml')!r}).with_values("
        "**{'rolling.turns': 40})\n"
        "def tell(self, label, done, total):\n"
        "    if done >= 1000 and not getattr(self, 'told', False):\n"
        "        self.told = True\n"
        "        print('IN THE TIME LOOP', done, flush=True)\n"
        "softway._Bar.__call__ = tell\n"
    )
    content, _ = execute(kc, setup)
    assert content["status"] == "ok", content

    # The interrupt is sent from another thread while execute() collects the cell's
    # messages, as a front end does.
    import threading

    fired = {}

    def interrupt():
        while "t" not in started:
            time.sleep(0.01)
        fired["t"] = time.monotonic()
        km.interrupt_kernel()

    t = threading.Thread(target=interrupt, daemon=True)
    t.start()
    # The cell notes when the exception reaches it (CLOCK_MONOTONIC: one clock for the
    # kernel's process and this one) and raises it on.
    cell = (
        "import time\n"
        "try:\n"
        "    r = softway.run(sc, progress=True)\n"
        "except softway.RunInterrupted:\n"
        "    print('RAISED AT', repr(time.monotonic()), flush=True)\n"
        "    raise\n"
    )
    content, messages = execute(kc, cell, on_message=watch, timeout=600)
    ended = time.monotonic()
    t.join(timeout=5)
    assert "t" in fired, "the run ended before the interrupt"
    assert content["status"] == "error", content
    assert content["ename"] == "RunInterrupted", content
    raised = float(stdout_of(messages).split("RAISED AT")[1].split()[0])
    # The run stops and its exception reaches the cell within a second of the signal;
    # the cell ends within seconds (IPython formats the traceback, the first time in a
    # kernel importing what it needs for that).
    print(f"signal -> RunInterrupted {raised - fired['t']:.3f} s, -> cell ended "
          f"{ended - fired['t']:.3f} s")
    assert 0 < raised - fired["t"] < 1.0, raised - fired["t"]
    assert ended - fired["t"] < 10.0, ended - fired["t"]

    # The exception the cell raised holds the partial result.
    check = (
        "import json\n"
        "e = sys.last_value\n"
        "print(json.dumps({'isinstance': isinstance(e, softway.RunInterrupted),\n"
        "  'keyboard': isinstance(e, KeyboardInterrupt),\n"
        "  'interrupted': e.result.interrupted,\n"
        "  'summary_interrupted': e.result.summary['interrupted'],\n"
        "  'steps': e.result.summary['steps'],\n"
        "  'rows': e.result.history.sizes['time']}))\n"
    )
    content, messages = execute(kc, check)
    assert content["status"] == "ok", content
    got = json.loads(stdout_of(messages).strip().splitlines()[-1])
    assert got["isinstance"] and got["keyboard"], got
    assert got["interrupted"] and got["summary_interrupted"] is True, got
    # 40 turns at 300 rad/s with h = 2e-6 s after 5 ms of settling.
    import math

    full = round((5e-3 + 40 * 2 * math.pi / 300.0) / 2e-6)
    assert 1000 <= got["steps"] < full // 4, got
    assert 0 < got["rows"] <= got["steps"] // 5 + 1, got


def _bar_cell(block_ipywidgets: bool) -> str:
    return (
        ("import sys; sys.modules['ipywidgets'] = None\n" if block_ipywidgets else "")
        + "import softway\n"
        + f"r = softway.run({str(SCENARIOS / 'wheel-paper-mesh.toml')!r}, progress=True, "
        + "**{'rolling.turns': 1})\n"
        + "print('STEPS', r.summary['steps'])\n"
    )


def test_the_progress_bar_is_a_widget_that_updates(kernel):
    """With ipywidgets: tqdm.auto draws a widget (display_data of a widget view) and the
    run updates its value through the widget's comm while the cell runs."""
    pytest.importorskip("ipywidgets")
    km, kc = kernel
    content, messages = execute(kc, _bar_cell(block_ipywidgets=False))
    assert content["status"] == "ok", content
    views = [
        m for m in messages
        if m["msg_type"] == "display_data"
        and "application/vnd.jupyter.widget-view+json" in m["content"]["data"]
    ]
    assert views, [m["msg_type"] for m in messages]
    # The bar's progress widget (tqdm's FloatProgress): opened over a comm, then its value
    # updated through that comm while the run goes.
    bars = {
        m["content"]["comm_id"]
        for m in messages
        if m["msg_type"] == "comm_open"
        and m["content"]["data"].get("state", {}).get("_model_name") == "FloatProgressModel"
    }
    assert len(bars) == 1, bars
    values = [
        m["content"]["data"]["state"]["value"]
        for m in messages
        if m["msg_type"] == "comm_msg"
        and m["content"]["comm_id"] in bars
        and "value" in m["content"]["data"].get("state", {})
    ]
    steps = int(stdout_of(messages).split("STEPS")[1])
    # Several updates, increasing, the last the run's steps (the bar counts steps).
    assert len(values) >= 2, values
    assert values == sorted(values) and values[-1] == steps, (values, steps)
    # No text bar on stderr: the widget is the bar.
    stderr = "".join(
        m["content"]["text"] for m in messages
        if m["msg_type"] == "stream" and m["content"]["name"] == "stderr"
    )
    assert "%|" not in stderr, stderr


def test_without_ipywidgets_the_bar_is_text(kernel):
    """Without ipywidgets (hidden from the kernel): tqdm.auto falls back to its text bar on
    stderr (with tqdm's warning that IProgress is missing), and the run completes."""
    km, kc = kernel
    content, messages = execute(kc, _bar_cell(block_ipywidgets=True))
    assert content["status"] == "ok", content
    stderr = "".join(
        m["content"]["text"] for m in messages
        if m["msg_type"] == "stream" and m["content"]["name"] == "stderr"
    )
    assert "step" in stderr and "%" in stderr, stderr
    assert int(stdout_of(messages).split("STEPS")[1]) > 1000
    assert not any(
        "application/vnd.jupyter.widget-view+json" in m["content"].get("data", {})
        for m in messages if m["msg_type"] == "display_data"
    )
