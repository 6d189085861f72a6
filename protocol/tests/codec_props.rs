//! Properties of the frame codec on the host: every command survives
//! encode -> parse -> decode, and no byte sequence can make the parser yield a
//! frame whose CRC is wrong, panic, or stay stuck inside a frame past the
//! timeout.

use henrytwo_protocol::crc::crc8;
use henrytwo_protocol::frame::{encode_frame, Event, Parser, MAX_FRAME, MAX_PAYLOAD, START};
use henrytwo_protocol::message::{Command, Test};
use henrytwo_protocol::param::Param;
use proptest::prelude::*;

fn frame_of(cmd: &Command) -> Vec<u8> {
    let mut payload = [0u8; MAX_PAYLOAD];
    let n = cmd.encode(&mut payload).unwrap();
    let mut out = [0u8; MAX_FRAME];
    let len = encode_frame(&payload[..n], &mut out).unwrap();
    out[..len].to_vec()
}

fn any_command() -> impl Strategy<Value = Command> {
    let test = prop_oneof![
        Just(Test::UmbmarkCw),
        Just(Test::UmbmarkCcw),
        Just(Test::Line),
        Just(Test::Triangle)
    ];
    let param = (1u8..=16).prop_map(|id| Param::from_u8(id).unwrap());
    prop_oneof![
        Just(Command::Ping),
        Just(Command::Stop),
        Just(Command::GetState),
        Just(Command::GetTelemetry),
        test.prop_map(Command::StartTest),
        param.clone().prop_map(Command::GetParam),
        (param, any::<f32>()).prop_map(|(p, v)| Command::SetParam(p, v)),
    ]
}

proptest! {
    /// A command's frame parses back to its payload, and the payload decodes
    /// to the command (SET_PARAM values outside their range are refused by
    /// decode, as the firmware refuses them).
    #[test]
    fn commands_round_trip(cmd in any_command()) {
        let bytes = frame_of(&cmd);
        let mut p = Parser::new(50);
        let mut payload = None;
        for &b in &bytes {
            if let Some(Event::Frame(f)) = p.push(b, 0) {
                payload = Some(f.to_vec());
            }
        }
        let payload = payload.expect("a whole frame parses");
        match Command::decode(&payload) {
            Ok(back) => match (cmd, back) {
                (Command::SetParam(a, x), Command::SetParam(b, y)) => {
                    prop_assert_eq!(a, b);
                    prop_assert_eq!(x.to_bits(), y.to_bits());
                }
                _ => prop_assert_eq!(back, cmd),
            },
            Err(_) => prop_assert!(matches!(cmd, Command::SetParam(..))),
        }
    }

    /// Whatever bytes arrive, a yielded frame always carries a correct CRC
    /// over its length and payload, and silence longer than the timeout
    /// always brings the parser back between frames.
    #[test]
    fn random_bytes_never_yield_a_bad_frame(bytes in proptest::collection::vec(any::<u8>(), 0..300)) {
        let mut p = Parser::new(50);
        let mut stream = Vec::new();
        for (i, &b) in bytes.iter().enumerate() {
            stream.push(b);
            if let Some(Event::Frame(f)) = p.push(b, i as u32) {
                let len = f.len() as u8;
                // The frame is the tail of the stream: START, LEN, payload, CRC.
                let n = stream.len();
                prop_assert!(n >= f.len() + 3);
                prop_assert_eq!(stream[n - f.len() - 3], START);
                let mut covered = vec![len];
                covered.extend_from_slice(f);
                prop_assert_eq!(crc8(&covered), stream[n - 1]);
            }
        }
        let later = bytes.len() as u32 + 1000;
        let _ = p.poll(later);
        prop_assert!(!p.in_frame());
    }
}
