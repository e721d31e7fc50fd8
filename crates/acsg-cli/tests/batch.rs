//! `acsg batch`: many task files in one run; a broken one is reported and skipped, a
//! rerun skips what is already written.

use std::path::{Path, PathBuf};

use assert_cmd::Command;
use predicates::str::contains;

fn fixture(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../fixtures")
        .join(name)
}

fn acsg() -> Command {
    Command::cargo_bin("acsg").expect("binary built")
}

/// 20 small tasks (the cube on the slab and the pinned peg in the hole, with varied
/// bounds) in `dir/tasks`, the 8th with a broken moving part; returns the manifest.
fn write_batch(dir: &Path) -> PathBuf {
    let tasks = dir.join("tasks");
    std::fs::create_dir_all(&tasks).unwrap();
    let mut names = Vec::new();
    for k in 0..20 {
        let (fixed, moving, bounds) = if k % 2 == 0 {
            let r = k + 1;
            (
                "slab.off",
                "cube.off",
                format!("x = [-1, 1]\ny = [0, 0]\nz = [0, 3]\nrx = [-{r}, {r}]\nry = [0, 0]\nrz = [0, 0]\n"),
            )
        } else {
            (
                "block_with_hole.off",
                "peg.off",
                format!(
                    "x = [-2, 2]\ny = [-2, 2]\nz = [0, {}]\nrx = [0, 0]\nry = [0, 0]\nrz = [0, 0]\n",
                    40 + k
                ),
            )
        };
        let moving = if k == 7 {
            fixture("bad/open_box.off")
        } else {
            fixture(moving)
        };
        let text = format!(
            "fixed = {:?}\nmoving = {:?}\n[bounds]\n{bounds}",
            fixture(fixed).display().to_string(),
            moving.display().to_string()
        );
        let name = format!("pair{k:02}.toml");
        std::fs::write(tasks.join(&name), text).unwrap();
        names.push(format!("\"tasks/{name}\""));
    }
    let manifest = dir.join("batch.toml");
    std::fs::write(
        &manifest,
        format!("tasks = [{}]\noutput_dir = \"graphs\"\n", names.join(", ")),
    )
    .unwrap();
    manifest
}

fn outputs(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir.join("graphs"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

#[test]
fn twenty_tasks_one_broken_gives_nineteen_graphs_and_one_clear_error() {
    let dir = tempfile::tempdir().unwrap();
    let manifest = write_batch(dir.path());
    acsg()
        .arg("batch")
        .arg(&manifest)
        .arg("--no-timings")
        .assert()
        .code(1)
        .stderr(contains("pair07.toml"))
        .stderr(contains("open_box.off"))
        .stderr(contains("not a valid solid"))
        .stderr(contains("1 of 20 tasks failed"))
        .stdout(contains("19 generated, 0 skipped (already written), 1 failed"));
    let written = outputs(dir.path());
    assert_eq!(written.len(), 19, "{written:?}");
    assert!(!written.contains(&"pair07.graph.json".to_string()));

    // Each output is what `acsg run` writes for its task alone.
    let alone = dir.path().join("alone.json");
    acsg()
        .arg("run")
        .arg(dir.path().join("tasks/pair03.toml"))
        .args(["--no-timings", "-q", "-o"])
        .arg(&alone)
        .assert()
        .success();
    assert_eq!(
        std::fs::read(&alone).unwrap(),
        std::fs::read(dir.path().join("graphs/pair03.graph.json")).unwrap()
    );
}

#[test]
fn a_rerun_skips_what_is_written_and_redoes_what_changed() {
    let dir = tempfile::tempdir().unwrap();
    let manifest = write_batch(dir.path());
    acsg().arg("batch").arg(&manifest).arg("-q").assert().code(1);
    let kept = dir.path().join("graphs/pair00.graph.json");
    let before = std::fs::read(&kept).unwrap();
    // One output removed, one task changed (wider z), the broken part repaired.
    std::fs::remove_file(dir.path().join("graphs/pair01.graph.json")).unwrap();
    let changed = dir.path().join("tasks/pair02.toml");
    let text = std::fs::read_to_string(&changed)
        .unwrap()
        .replace("z = [0, 3]", "z = [0, 4]");
    std::fs::write(&changed, text).unwrap();
    let repaired = dir.path().join("tasks/pair07.toml");
    let text = std::fs::read_to_string(&repaired).unwrap().replace(
        &fixture("bad/open_box.off").display().to_string(),
        &fixture("peg.off").display().to_string(),
    );
    std::fs::write(&repaired, text).unwrap();
    acsg()
        .arg("batch")
        .arg(&manifest)
        .assert()
        .success()
        .stdout(contains("3 generated, 17 skipped (already written), 0 failed"))
        .stdout(contains("skipped"));
    // Not rewritten: the stage times of the first run are still there.
    assert_eq!(std::fs::read(&kept).unwrap(), before);
    assert_eq!(outputs(dir.path()).len(), 20);
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("graphs/pair02.graph.json")).unwrap()).unwrap();
    assert_eq!(v["bounds"]["max"][2], 4.0);
    // --force generates everything again.
    acsg()
        .arg("batch")
        .arg(&manifest)
        .arg("--force")
        .assert()
        .success()
        .stdout(contains("20 generated, 0 skipped"));
}

#[test]
fn bad_manifests_are_refused_clearly() {
    let dir = tempfile::tempdir().unwrap();
    let manifest = dir.path().join("m.toml");
    std::fs::write(&manifest, "task = [\"a.toml\"]\n").unwrap();
    acsg()
        .arg("batch")
        .arg(&manifest)
        .assert()
        .code(1)
        .stderr(contains("m.toml"))
        .stderr(contains("tasks = ["));
    std::fs::write(
        &manifest,
        "tasks = [\"a/x.toml\", \"b/x.toml\"]\noutput_dir = \"out\"\n",
    )
    .unwrap();
    acsg()
        .arg("batch")
        .arg(&manifest)
        .assert()
        .code(1)
        .stderr(contains("would both write"));
    acsg()
        .arg("batch")
        .arg(dir.path().join("missing.toml"))
        .assert()
        .code(1)
        .stderr(contains("cannot read the manifest"));
}

/// A graph written by one strategy is not the output of a task asking for another: a
/// rerun after the task file changes its strategy generates it again.
#[test]
fn a_task_that_changes_its_strategy_is_generated_again() {
    let dir = tempfile::tempdir().unwrap();
    let task = dir.path().join("cube.toml");
    let text = format!(
        "fixed = {:?}\nmoving = {:?}\n[bounds]\nx = [-1, 1]\ny = [0, 0]\nz = [0, 3]\nrx = [-5, 5]\nry = [0, 0]\n\
         rz = [0, 0]\n",
        fixture("slab.off").display().to_string(),
        fixture("cube.off").display().to_string()
    );
    std::fs::write(&task, &text).unwrap();
    let manifest = dir.path().join("batch.toml");
    std::fs::write(&manifest, "tasks = [\"cube.toml\"]\n").unwrap();
    let batch = || acsg().arg("batch").arg(&manifest).assert().success();
    batch().stdout(contains("1 generated, 0 skipped"));
    batch().stdout(contains("0 generated, 1 skipped"));
    std::fs::write(&task, format!("{text}[options]\nstrategy = \"paper\"\n")).unwrap();
    batch().stdout(contains("1 generated, 0 skipped"));
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("cube.graph.json")).unwrap()).unwrap();
    assert_eq!(v["options"]["strategy"], "paper");
    batch().stdout(contains("0 generated, 1 skipped"));
}
