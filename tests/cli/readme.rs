//! The README's two set-up commands stay true: `.ci/run` runs exactly the README's test command.

use super::harness::root;

#[test]
fn ci_runs_the_readme_test_command() {
    let readme = std::fs::read_to_string(root().join("README.md")).unwrap();
    let ci = std::fs::read_to_string(root().join(".ci/run")).unwrap();
    let block = readme
        .split("```sh\n")
        .nth(1)
        .expect("README opens with a sh block");
    let lines: Vec<&str> = block
        .lines()
        .take_while(|l| !l.starts_with("```"))
        .collect();
    assert_eq!(lines.len(), 2, "two commands: the main job and the tests");
    assert!(lines[0].contains("process/mis-grasper.yaml"));
    let test_cmd = lines[1].split("   #").next().unwrap().trim();
    assert!(
        ci.lines().any(|l| l.trim() == test_cmd),
        "`.ci/run` must run `{test_cmd}`"
    );
}
