"""acsg.generate_many: a batch of pairs, in order, each a Graph or its exception; a
rerun reads the outputs already written instead of generating them again."""

import os

import pytest

import acsg
from conftest import fixture, without_timings

PAIRS = [("slab.off", "cube.off"), ("block_with_hole.off", "peg.off")]


def tasks(tmp_path=None):
    """20 small tasks, the 8th with a broken part."""
    out = []
    for k in range(20):
        fixed, moving = PAIRS[k % 2]
        if k % 2 == 0:
            bounds = {"x": (-1, 1), "z": (0, 3), "rx": (-(k + 1), k + 1)}
        else:
            bounds = {"x": (-2, 2), "y": (-2, 2), "z": (0, 40 + k)}
        task = {"fixed": fixture(fixed), "moving": fixture(moving), "bounds": bounds}
        if k == 7:
            task["moving"] = fixture("bad/open_box.off")
        if tmp_path is not None:
            task["output"] = str(tmp_path / f"pair{k}.graph.json")
        out.append(task)
    return out


def test_twenty_pairs_one_broken(tmp_path):
    calls = []
    results = acsg.generate_many(tasks(tmp_path), progress=lambda done, total: calls.append((done, total)))
    assert len(results) == 20
    errors = [k for k, r in enumerate(results) if isinstance(r, Exception)]
    assert errors == [7]
    assert isinstance(results[7], acsg.AcsgError)
    assert "open_box.off" in str(results[7]) and "not a valid solid" in str(results[7])
    assert sum(isinstance(r, acsg.Graph) for r in results) == 19
    assert calls == [(k + 1, 20) for k in range(20)]
    # Each graph is the one generate gives for that pair alone, saved where asked.
    for k in (0, 1, 18):
        task = dict(tasks()[k])
        alone = acsg.generate(**task)
        assert without_timings(results[k].document) == without_timings(alone.document)
        assert acsg.Graph.load(tmp_path / f"pair{k}.graph.json").to_json() == results[k].to_json()
    assert not (tmp_path / "pair7.graph.json").exists()


def test_a_rerun_skips_the_pairs_already_written(tmp_path):
    first = acsg.generate_many(tasks(tmp_path)[:4])
    stamps = {k: os.stat(tmp_path / f"pair{k}.graph.json").st_mtime_ns for k in (0, 1, 2, 3)}
    # One output removed, one changed task: those two are generated again.
    os.remove(tmp_path / "pair1.graph.json")
    changed = tasks(tmp_path)[:4]
    changed[2]["bounds"] = {"x": (-1, 1), "z": (0, 4)}
    again = acsg.generate_many(changed)
    # Read back, not generated: the very same document, stage times included.
    assert again[0].document == first[0].document
    assert again[3].document == first[3].document
    assert os.stat(tmp_path / "pair0.graph.json").st_mtime_ns == stamps[0]
    assert (tmp_path / "pair1.graph.json").exists()
    assert again[2].bounds["z"] == (0.0, 4.0)
    assert os.stat(tmp_path / "pair2.graph.json").st_mtime_ns != stamps[2]


def test_bad_tasks_are_results_too():
    results = acsg.generate_many([{"fixed": fixture("slab.off")}, "not a task", {**tasks()[0], "bounds": {"z": (1, 0)}}])
    assert isinstance(results[0], TypeError)
    assert isinstance(results[1], TypeError)
    assert isinstance(results[2], ValueError) and "invalid bounds" in str(results[2])
