//! What the firmware sent on each USART over a run, from reset to the end,
//! named as the board names its links: a sketch's `Serial` prints (USART0,
//! the board's `debug_uart`) as much as the command link's replies. On an
//! MCU with USB, its USB serial (the Leonardo core's `Serial`) too, named
//! `usb_serial`.

use std::fmt::Write;

use crate::bench::{Bench, USB_SERIAL};

/// The ATmega2560's USARTs: 0-3.
const USARTS: u8 = 4;

/// The output of one USART over a run.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct UartOutput {
    /// The board's name for the link on it (`debug_uart`, `command_uart`),
    /// `usartN` for one the board does not wire that the firmware used, or
    /// `usb_serial`.
    pub name: String,
    /// The USART's number; 4 for the USB serial.
    pub usart: u8,
    /// The board's baud rate for it; None for a USART the board does not wire.
    pub baud: Option<u32>,
    /// The bytes as text (UTF-8; a byte that is not, as U+FFFD).
    pub text: String,
    pub bytes: Vec<u8>,
}

/// Every USART's output on `bench` so far: each link of the board (sent
/// on or not), then any other USART the firmware sent on.
pub(crate) fn outputs(bench: &Bench) -> Vec<UartOutput> {
    let links = bench.board().uarts();
    let usb = bench.board().mcu.chip().usb.map(|_| UartOutput {
        name: "usb_serial".into(),
        usart: USB_SERIAL,
        baud: None,
        text: String::from_utf8_lossy(bench.uart_output(USB_SERIAL)).into_owned(),
        bytes: bench.uart_output(USB_SERIAL).to_vec(),
    });
    (0..USARTS)
        .filter_map(|n| {
            let link = links.iter().find(|(_, u)| u.usart == n);
            let bytes = bench.uart_output(n);
            if link.is_none() && bytes.is_empty() {
                return None;
            }
            Some(UartOutput {
                name: link.map_or_else(|| format!("usart{n}"), |(name, _)| (*name).to_string()),
                usart: n,
                baud: link.map(|(_, u)| u.baud),
                text: String::from_utf8_lossy(bytes).into_owned(),
                bytes: bytes.to_vec(),
            })
        })
        .chain(usb)
        .collect()
}

impl UartOutput {
    /// Whether its bytes read as text: UTF-8 without control characters
    /// other than line ends and tabs (a framed protocol's bytes do not).
    pub fn is_text(&self) -> bool {
        std::str::from_utf8(&self.bytes)
            .is_ok_and(|t| t.chars().all(|c| !c.is_control() || "\r\n\t".contains(c)))
    }
}

/// Each output for a person: a head line (name, USART, baud, byte count),
/// then its text line by line or, when it is not text, its bytes in hex,
/// each line indented by `indent`.
pub fn render(outputs: &[UartOutput], indent: &str) -> String {
    let mut s = String::new();
    for u in outputs {
        let link = match u.baud {
            _ if u.usart == USB_SERIAL => "USB CDC".to_string(),
            Some(b) => format!("USART{}, {b} baud", u.usart),
            None => format!("USART{}, not on the board", u.usart),
        };
        let kind = match (u.bytes.is_empty(), u.is_text()) {
            (true, _) => "",
            (false, true) => ", text:",
            (false, false) => ", not text, in hex:",
        };
        let _ = writeln!(
            s,
            "{indent}{} ({link}): {} bytes{kind}",
            u.name,
            u.bytes.len()
        );
        if u.bytes.is_empty() {
            continue;
        }
        if u.is_text() {
            for line in u.text.trim_end_matches(['\r', '\n']).split('\n') {
                let _ = writeln!(s, "{indent}  | {}", line.trim_end_matches('\r'));
            }
        } else {
            for chunk in u.bytes.chunks(16) {
                let hex: Vec<String> = chunk.iter().map(|b| format!("{b:02x}")).collect();
                let _ = writeln!(s, "{indent}  {}", hex.join(" "));
            }
        }
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    fn out(bytes: &[u8]) -> UartOutput {
        UartOutput {
            name: "debug_uart".into(),
            usart: 0,
            baud: Some(9600),
            text: String::from_utf8_lossy(bytes).into_owned(),
            bytes: bytes.to_vec(),
        }
    }

    /// Text prints line by line; a frame's bytes print in hex; nothing sent
    /// is said as 0 bytes.
    #[test]
    fn text_is_shown_as_lines_and_bytes_as_hex() {
        let r = render(&[out(b"ready\r\nleg 1\r\n")], "  ");
        assert_eq!(
            r,
            "  debug_uart (USART0, 9600 baud): 14 bytes, text:\n  | ready\n  | leg 1\n"
                .replace("  | ", "    | ")
        );
        let r = render(&[out(&[0xaa, 0x01, 0x00])], "");
        assert_eq!(
            r,
            "debug_uart (USART0, 9600 baud): 3 bytes, not text, in hex:\n  aa 01 00\n"
        );
        let mut none = out(b"");
        none.name = "usart2".into();
        none.usart = 2;
        none.baud = None;
        assert_eq!(
            render(&[none], ""),
            "usart2 (USART2, not on the board): 0 bytes\n"
        );
    }
}
