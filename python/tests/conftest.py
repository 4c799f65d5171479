"""Shared test set-up.

Ctrl-C reaches Python as SIGINT through `signal.default_int_handler`, which raises
KeyboardInterrupt. A Python started with SIGINT ignored (a command run in the background
by a shell without job control, `cmd &`, inherits SIG_IGN, and Python then installs no
handler) never raises it, and `_thread.interrupt_main()` does nothing. The interrupt tests
simulate a user's Ctrl-C in a terminal or a notebook, where the handler is there: each test
runs with it installed, the previous one restored after.
"""

import signal
import threading

import pytest


@pytest.fixture(autouse=True)
def _python_sigint_handler():
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, previous)
