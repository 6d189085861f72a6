//! `hil board check FILE`: a board TOML decoded, or why it is refused.

use std::path::PathBuf;

use anyhow::Result;
use hil::board::{Board, BoardError};

/// Board descriptions.
#[derive(clap::Args)]
pub struct BoardCmd {
    #[command(subcommand)]
    command: BoardCommand,
}

#[derive(clap::Subcommand)]
enum BoardCommand {
    /// Load and check a board TOML; print the decoded board (pins with
    /// their ports and timer channels) and the robust firmware's driver
    /// parameters for it, or each problem on a line of its own.
    Check {
        /// The board TOML (e.g. fixtures/boards/henrytwo.toml).
        #[arg(value_name = "FILE")]
        file: PathBuf,
        /// The board is for a firmware of your own (run with --tests): skip
        /// the check that the robust firmware can read its encoders.
        #[arg(long)]
        own_firmware: bool,
    },
}

impl BoardCmd {
    pub fn run(self) -> Result<()> {
        let BoardCommand::Check { file, own_firmware } = self.command;
        match Board::load(&file) {
            Ok(board) => {
                if let Some(why) = board.firmware_encoder_mismatch().filter(|_| !own_firmware) {
                    // Refused as every run of the robust firmware refuses it.
                    return Err(super::BadInput(format!("{}: {why}", file.display())).into());
                }
                let params: serde_json::Map<String, serde_json::Value> = board
                    .firmware_params()
                    .into_iter()
                    .map(|(p, v)| (p.name().to_string(), v.into()))
                    .collect();
                let out = serde_json::json!({ "board": board, "firmware_params": params });
                println!("{}", serde_json::to_string_pretty(&out)?);
                Ok(())
            }
            Err(BoardError::Invalid(problems)) => {
                for p in &problems {
                    eprintln!("{p}");
                }
                // Refused input, as `--board` refuses it in `hil run` (exit 2).
                Err(
                    super::BadInput(format!("{}: {} problem(s)", file.display(), problems.len()))
                        .into(),
                )
            }
            Err(e) => Err(super::bad_input(e)),
        }
    }
}

/// `--board FILE`: the board, loaded and checked as the argument is parsed;
/// its problems on one line (the CLI's errors are one line each).
pub fn parse_board(path: &str) -> Result<Board, String> {
    Board::load(path).map_err(|e| match e {
        BoardError::Invalid(problems) => problems
            .iter()
            .map(ToString::to_string)
            .collect::<Vec<_>>()
            .join("; "),
        e => e.to_string(),
    })
}
