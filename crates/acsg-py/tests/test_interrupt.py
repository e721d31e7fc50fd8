"""Ctrl-C during a long generation stops it soon, with KeyboardInterrupt, and the
package still works afterwards."""

import signal
import threading
import time

import pytest

import acsg
from conftest import fixture


@pytest.mark.skipif(not hasattr(signal, "pthread_kill"), reason="needs POSIX signals")
def test_sigint_stops_a_long_run():
    # The demo's pair and bounds: tens of seconds when left to run.
    bounds = {"x": (-5, 5), "y": (-5, 5), "z": (0, 240), "rx": (-18, 18), "ry": (-18, 18), "rz": (-18, 18)}
    main = threading.main_thread().ident
    timer = threading.Timer(1.0, lambda: signal.pthread_kill(main, signal.SIGINT))
    # Python's own Ctrl-C handler, as in a terminal: a process started in the
    # background by a shell inherits SIGINT ignored, and then no Ctrl-C arrives at all.
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    start = time.monotonic()
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            acsg.generate(fixture("l_block.off"), fixture("box.off"), bounds=bounds)
    finally:
        timer.cancel()
        signal.signal(signal.SIGINT, previous)
    assert time.monotonic() - start < 10.0
    # Nothing is left broken: a small run still works.
    graph = acsg.generate(fixture("slab.off"), fixture("cube.off"), bounds={"z": (0, 3)})
    assert len(graph.states) >= 2
