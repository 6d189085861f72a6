//! The station page on a serial port: `hil serve --pty` offered with
//! `hil ui --port`, opened by the page like a real device.

use super::*;

/// The same page drives a robot on a serial port: here `hil serve --pty`,
/// offered with `hil ui --port`, opened by the page like a real device.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn the_page_drives_a_robot_on_a_serial_port() {
    let elf = support::firmware_path("robust");
    let mut serve = Command::new(env!("CARGO_BIN_EXE_hil"))
        .args(["serve", "--pty", "--speed", "10", "--elf"])
        .arg(&elf)
        .arg("--robot")
        .arg(hil::paths::robot_config("henrytwo-ideal"))
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .expect("hil serve starts");
    let mut line = String::new();
    BufReader::new(serve.stdout.take().unwrap())
        .read_line(&mut line)
        .unwrap();
    let serve = Killed(serve);
    let pty = line.trim().strip_prefix("pty: ").unwrap().to_string();
    let sessions = std::env::temp_dir().join(format!("station-serial-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&sessions);
    let (_ui, url) = ui(&sessions, &["--port", &pty]);
    let (c, _driver) = browser(&sessions.join("chromium-profile")).await;
    c.goto(&url).await.unwrap();
    // --port preselects the device.
    c.wait()
        .at_most(Duration::from_secs(10 * super::SLACK))
        .for_element(Locator::Css("#robot-select option"))
        .await
        .unwrap();
    let selected = c
        .find(Locator::Id("robot-select"))
        .await
        .unwrap()
        .prop("value")
        .await
        .unwrap();
    assert_eq!(selected.as_deref(), Some(format!("serial:{pty}").as_str()));
    click(&c, Locator::Id("connect")).await;
    wait_text(&c, "status", 30, |t| t.starts_with("connected:")).await;
    type_into(&c, "leg-mm", "200").await;
    click(&c, Locator::Css("button[data-test='line']")).await;
    wait_text(&c, "notice", 60, |t| t.contains("line done")).await;
    // A serial robot shows no pose: the page says to measure the floor.
    assert!(text(&c, "pose").await.contains("measure"));
    let file = hil::clients::station::session::file_name(&format!("serial-{pty}"));
    assert!(sessions.join(&file).exists(), "no session file {file}");

    // The port vanishes: the page says so.
    drop(serve);
    wait_text(&c, "status", 20, |t| t.contains("is gone")).await;
    c.close().await.unwrap();
    let _ = std::fs::remove_dir_all(&sessions);
}
