"""acsg.ray.generate_many on a local Ray instance with 2 CPUs: each result is the
single-process one."""

import os
import pickle

import pytest

import acsg
from conftest import without_timings
from test_batch import tasks


def test_errors_pickle():
    error = pickle.loads(pickle.dumps(acsg.AcsgError("broken part")))
    assert isinstance(error, acsg.AcsgError) and str(error) == "broken part"


def test_ray_gives_the_single_process_results(tmp_path):
    if os.environ.get("CI"):
        import ray  # CI installs ray: a missing one is a failure there
    else:
        ray = pytest.importorskip("ray")
    import acsg.ray

    batch = tasks()[4:10]  # the broken pair (7) among them
    ray.init(num_cpus=2, include_dashboard=False, log_to_driver=False)
    try:
        remote = acsg.ray.generate_many(batch)
    finally:
        ray.shutdown()
    local = acsg.generate_many(batch)
    assert len(remote) == len(local) == 6
    assert [isinstance(r, Exception) for r in local] == [False, False, False, True, False, False]
    for r, l in zip(remote, local):
        if isinstance(l, Exception):
            assert type(r) is type(l) and str(r) == str(l)
        else:
            assert isinstance(r, acsg.Graph), r
            assert without_timings(r.document) == without_timings(l.document)
