//! The station's options, without a browser.

use super::*;

/// The emulated robots run on the board and seed of the command line (`hil ui --board
/// ... --seed ...`), and their link at that board's baud rate.
#[test]
fn emulated_robots_are_served_on_the_board_asked_for() {
    let board = crate::board::Board::load(
        crate::paths::workspace_root().join("fixtures/boards/rover65.toml"),
    )
    .unwrap();
    assert_ne!(board, crate::board::Board::default());
    let options = UiOptions {
        sessions_dir: PathBuf::new(),
        robots: vec![],
        firmware: crate::firmware::elf::Firmware::load(&crate::paths::firmware_elf("robust"))
            .unwrap(),
        port: None,
        baud: 9600,
        bench: BenchOptions {
            seed: 7,
            board,
            ..Default::default()
        },
        description: None,
    };
    let served = options.serve_options(2.5);
    assert_eq!(served.speed, 2.5);
    assert_eq!(served.bench.board, board);
    assert_eq!(served.bench.seed, 7);
}

#[test]
fn a_config_given_on_the_command_line_else_the_reference_robot_leads_the_list() {
    let dir = std::env::temp_dir().join(format!("station-robots-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for f in ["b.toml", "a.toml", "notes.txt"] {
        std::fs::write(dir.join(f), "").unwrap();
    }
    let names = |v: Vec<(String, PathBuf)>| v.into_iter().map(|(n, _)| n).collect::<Vec<_>>();
    assert_eq!(names(robot_configs(&dir, None)), ["a", "b"]);
    assert_eq!(
        names(robot_configs(&dir, Some(dir.join("b.toml")))),
        ["b", "a"]
    );
    // The reference robot leads when no config was given.
    std::fs::write(
        dir.join(format!("{}.toml", crate::paths::REFERENCE_ROBOT)),
        "",
    )
    .unwrap();
    assert_eq!(
        names(robot_configs(&dir, None)),
        [crate::paths::REFERENCE_ROBOT, "a", "b"]
    );
    assert_eq!(
        names(robot_configs(&dir, Some(dir.join("b.toml")))),
        ["b", "a", crate::paths::REFERENCE_ROBOT]
    );
    let _ = std::fs::remove_dir_all(&dir);
}
