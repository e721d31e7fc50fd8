"""acsg.generate and the Graph it returns, checked against the CLI's JSON for the same
input, against acsg.contacts at every witness, and through networkx."""

import json

import numpy as np
import pytest

import acsg
from conftest import fixture, without_timings

# (fixed, moving, CLI bounds, Python bounds): small runs (well under a second).
CASES = {
    "peg_in_hole_pinned": (
        "block_with_hole.off",
        "peg.off",
        "x=-2:2,y=-2:2,z=0:45",
        {"x": (-2, 2), "y": (-2, 2), "z": (0, 45)},
    ),
    "cube_on_slab": (
        "slab.off",
        "cube.off",
        "x=-1:1,y=-1:1,z=0:3,rx=-10:10,ry=-10:10,rz=-180:180",
        {"x": (-1, 1), "y": (-1, 1), "z": (0, 3), "rx": (-10, 10), "ry": (-10, 10), "rz": (-180, 180)},
    ),
}


@pytest.fixture(scope="module", params=sorted(CASES))
def case(request):
    fixed, moving, spec, bounds = CASES[request.param]
    graph = acsg.generate(fixture(fixed), fixture(moving), bounds=bounds)
    return fixture(fixed), fixture(moving), spec, graph


def test_the_document_is_the_clis(case, cli):
    fixed, moving, spec, graph = case
    reference = json.loads(cli("generate", fixed, moving, "--bounds", spec, "--no-timings", "-q"))
    assert without_timings(graph.document) == reference
    # The objects say what the document says.
    assert len(graph.states) == len(reference["states"]) == graph.stats["states"]
    assert graph.edges == [tuple(e) for e in reference["edges"]]
    assert graph.complete is reference["complete"]
    for state, record in zip(graph.states, reference["states"]):
        assert state.id == record["id"]
        assert state.dof == record["dof"] and state.degenerate == record["degenerate"]
        assert [list(c.key) for c in state.contacts] == [[c["type"], c["fixed"], c["moving"]] for c in record["contacts"]]
        if record["witness"] is None:
            assert state.witness is None
        else:
            assert list(state.witness.pose) == record["witness"]["pose"]
            assert state.witness.matrix.shape == (4, 4)
            assert state.witness.matrix.tolist() == record["witness"]["matrix"]


def test_each_witness_shows_its_state(case):
    fixed, moving, _, graph = case
    a, b = acsg.part(fixed), acsg.part(moving)
    checked = 0
    for state in graph.states:
        if state.witness is None:
            continue
        at_matrix = acsg.contacts(a, b, state.witness.matrix)
        assert at_matrix.keys == state.keys, state
        assert at_matrix.penetration == 0.0
        at_pose = acsg.contacts(a, b, state.witness.pose, degrees=False)
        assert at_pose.keys == state.keys
        np.testing.assert_allclose(at_pose.matrix, state.witness.matrix, rtol=0, atol=1e-12)
        at_degrees = acsg.contacts(a, b, state.witness.pose_degrees)
        assert at_degrees.keys == state.keys
        checked += 1
    assert checked >= len(graph.states) - 1


def test_contacts_name_elements_with_geometry(case):
    _, _, _, graph = case
    doc = graph.document
    for state in graph.states:
        for c in state.contacts:
            for element, part in ((c.fixed_element, doc["fixed"]), (c.moving_element, doc["moving"])):
                assert element.id == element.kind[0] + str(element.index)
                if element.kind == "face":
                    outer = part["faces"][element.index][0]
                    assert element.points.tolist() == [part["vertices"][v] for v in outer]
                    assert element.normal.tolist() == part["face_normals"][element.index]
                elif element.kind == "edge":
                    assert element.points.tolist() == [part["vertices"][v] for v in part["edges"][element.index]]
                else:
                    assert element.points.tolist() == [part["vertices"][element.index]]


def test_networkx_graph_has_the_states_and_edges(case):
    nx = pytest.importorskip("networkx")
    _, _, _, graph = case
    g = graph.to_networkx()
    assert isinstance(g, nx.Graph)
    assert g.number_of_nodes() == len(graph.states)
    assert g.number_of_edges() == len(graph.edges) == graph.stats["edges"]
    assert sorted(tuple(sorted(e)) for e in g.edges) == sorted(graph.edges)
    for state in graph.states:
        node = g.nodes[state.id]
        assert node["dof"] == state.dof and isinstance(node["dof"], int)
        assert node["n_contacts"] == len(state.contacts)
        assert node["contacts"] == list(state.keys)
        if state.witness is not None:
            assert isinstance(node["matrix"], np.ndarray) and node["matrix"].shape == (4, 4)
            assert node["witness"].tolist() == list(state.witness.pose)
    assert g.graph["complete"] == graph.complete


def test_save_and_load_round_trip(case, tmp_path, cli):
    _, _, _, graph = case
    path = tmp_path / "graph.json"
    graph.save(path)
    again = acsg.Graph.load(path)
    assert again.document == graph.document
    assert again.to_json() == graph.to_json()
    # The CLI reads what Python saved.
    dot = cli("export", str(path), "--format", "dot")
    assert dot.startswith("graph") or dot.startswith("strict graph") or "--" in dot
    assert acsg.Graph.from_json(graph.to_json()).document == graph.document


def test_assembled_as_pose_or_matrix():
    # The peg lifted by 5 along z and turned 90 degrees: the same graph either way.
    pose = [0.0, 0.0, 0.0, 0.0, 0.0, 90.0]
    args = (fixture("block_with_hole.off"), fixture("peg.off"))
    bounds = {"x": (-2, 2), "y": (-2, 2), "z": (0, 45)}
    by_pose = acsg.generate(*args, bounds=bounds, assembled=pose)
    c, s = 0.0, 1.0
    matrix = np.array([[c, -s, 0, 0], [s, c, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]])
    matrix[0, 0] = matrix[1, 1] = np.cos(np.radians(90.0))
    matrix[1, 0], matrix[0, 1] = np.sin(np.radians(90.0)), -np.sin(np.radians(90.0))
    by_matrix = acsg.generate(*args, bounds=bounds, assembled=matrix)
    assert [s.keys for s in by_pose.states] == [s.keys for s in by_matrix.states]
    np.testing.assert_allclose(by_pose.assembled, matrix, atol=1e-15)


def test_threads_and_radians_give_the_same_graph():
    args = (fixture("slab.off"), fixture("cube.off"))
    degrees = acsg.generate(*args, bounds={"z": (0, 3), "rx": (-10, 10)}, threads=1)
    r = float(np.radians(10.0))
    radians = acsg.generate(*args, bounds=([0, 0, 0, -r, 0, 0], [0, 0, 3, r, 0, 0]), degrees=False, threads=2)
    assert without_timings(degrees.document) == without_timings(radians.document)


def test_progress_callback_and_bar(capsys):
    calls = []
    args = (fixture("slab.off"), fixture("cube.off"))
    bounds = {"z": (0, 3), "rx": (-10, 10), "ry": (-10, 10)}
    acsg.generate(*args, bounds=bounds, progress=lambda *p: calls.append(p))
    assert calls and all(stage in (1, 2) and 0 <= done <= total for stage, done, total, _ in calls)
    acsg.generate(*args, bounds=bounds, progress=True)
    assert "acsg" in capsys.readouterr().err


def test_an_error_in_the_progress_callback_stops_the_run():
    def fail(*_):
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        acsg.generate(fixture("slab.off"), fixture("cube.off"), bounds={"z": (0, 3)}, progress=fail)

    class Stop(Exception):
        pass

    def stop(*_):
        raise Stop("enough")

    with pytest.raises(Stop, match="enough"):
        acsg.generate(fixture("slab.off"), fixture("cube.off"), bounds={"z": (0, 3)}, progress=stop)


def test_bad_bounds_and_options_are_value_errors():
    args = (fixture("slab.off"), fixture("cube.off"))
    with pytest.raises(ValueError, match="invalid bounds"):
        acsg.generate(*args, bounds={"z": (3, 0)})
    with pytest.raises(ValueError, match="unknown bounds component"):
        acsg.generate(*args, bounds={"w": (0, 1)})
    with pytest.raises(ValueError, match="180"):
        acsg.generate(*args, bounds={"rz": (-200, 200)})
    with pytest.raises(ValueError, match="threads"):
        acsg.generate(*args, bounds={"z": (0, 1)}, threads=10**6)
    with pytest.raises(ValueError, match="not a rigid transform"):
        acsg.generate(*args, bounds={"z": (0, 1)}, assembled=np.diag([2.0, 1, 1, 1]))
    with pytest.raises(ValueError, match="6 values"):
        acsg.contacts(*args, [0, 0, 0])
    with pytest.raises(ValueError, match="unknown strategy 'fastest'"):
        acsg.generate(*args, bounds={"z": (0, 1)}, strategy="fastest")


def test_the_paper_strategy_is_named_and_never_complete():
    args = (fixture("slab.off"), fixture("cube.off"))
    bounds = {"x": (-1, 1), "y": (-1, 1), "z": (0, 3), "rx": (-10, 10), "ry": (-10, 10), "rz": (-180, 180)}
    paper = acsg.generate(*args, bounds=bounds, strategy="paper").document
    full = acsg.generate(*args, bounds=bounds).document
    assert paper["options"]["strategy"] == "paper"
    assert "strategy" not in full["options"]
    assert paper["complete"] is False and full["complete"] is True
    # Every state the paper's algorithm finds, the default finds too.
    def states(doc):
        return {tuple((c["type"], c["fixed"], c["moving"]) for c in s["contacts"]) for s in doc["states"]}
    assert len(states(paper)) > 1
    assert states(paper) <= states(full)


def test_bad_graph_files_raise_acsg_error(tmp_path):
    path = tmp_path / "g.json"
    path.write_text("{}")
    with pytest.raises(acsg.AcsgError, match="not an acsg graph"):
        acsg.Graph.load(path)
    with pytest.raises(acsg.AcsgError, match="cannot read"):
        acsg.Graph.load(tmp_path / "missing.json")


def test_node_link_export_reads_into_the_same_networkx_graph(case, cli, tmp_path):
    nx = pytest.importorskip("networkx")
    _, _, _, graph = case
    path = tmp_path / "graph.json"
    graph.save(path)
    data = json.loads(cli("export", str(path), "--format", "node-link"))
    try:
        g = nx.node_link_graph(data, edges="links")
    except TypeError:  # networkx before 3.4 has no `edges` argument
        g = nx.node_link_graph(data)
    mine = graph.to_networkx()
    assert sorted(g.nodes) == sorted(mine.nodes)
    assert sorted(tuple(sorted(e)) for e in g.edges) == sorted(tuple(sorted(e)) for e in mine.edges)
    for n in mine.nodes:
        a, b = g.nodes[n], mine.nodes[n]
        assert (a["dof"], a["degenerate"], a["n_contacts"]) == (b["dof"], b["degenerate"], b["n_contacts"])
        assert [tuple(c) for c in a["contacts"]] == b["contacts"]
        if b["witness"] is None:
            assert a["witness"] is None and a["matrix"] is None
        else:
            # Exactly the JSON's numbers: no digit lost on the way through the CLI.
            assert a["witness"] == b["witness"].tolist()
            assert a["matrix"] == b["matrix"].tolist()
    assert g.graph["complete"] == graph.complete
