//! Properties of the frame codec on the host: every command survives
//! encode -> parse -> decode (a SET_PARAM exactly when its value is in the
//! documented range, else it is refused with OutOfRange), and no byte sequence can make the parser yield a
//! frame whose CRC is wrong, panic, or stay stuck inside a frame past the
//! timeout.

use henrytwo_protocol::crc::crc8;
use henrytwo_protocol::frame::{encode_frame, Event, Parser, MAX_FRAME, MAX_PAYLOAD, START};
use henrytwo_protocol::message::{Command, Status, Test};
use henrytwo_protocol::param::Param;
use proptest::prelude::*;

fn frame_of(cmd: &Command) -> Vec<u8> {
    let mut payload = [0u8; MAX_PAYLOAD];
    let n = cmd.encode(&mut payload).unwrap();
    let mut out = [0u8; MAX_FRAME];
    let len = encode_frame(&payload[..n], &mut out).unwrap();
    out[..len].to_vec()
}

/// Every command but SET_PARAM: all of them valid, so each must decode back.
fn any_valid_command() -> impl Strategy<Value = Command> {
    let test = prop_oneof![
        Just(Test::UmbmarkCw),
        Just(Test::UmbmarkCcw),
        Just(Test::Line),
        Just(Test::Triangle)
    ];
    let param = (1u8..=Param::ALL.len() as u8).prop_map(|id| Param::from_u8(id).unwrap());
    prop_oneof![
        Just(Command::Ping),
        Just(Command::Stop),
        Just(Command::GetState),
        Just(Command::GetTelemetry),
        test.prop_map(Command::StartTest),
        param.prop_map(Command::GetParam),
    ]
}

/// A value inside `p`'s documented range: either edge, or anywhere between
/// (a whole number for the integer parameters).
fn in_range(p: Param) -> BoxedStrategy<f32> {
    let r = p.range();
    let between = (r.min..=r.max).prop_map(move |v| if r.integer { v.round() } else { v });
    prop_oneof![Just(r.min), Just(r.max), between].boxed()
}

/// Any bit pattern at all: mostly outside every range (huge, tiny, negative,
/// NaN, infinite), sometimes inside.
fn any_value(_: Param) -> BoxedStrategy<f32> {
    any::<u32>().prop_map(f32::from_bits).boxed()
}

/// A value just outside `p`'s range, or a fraction of an integer parameter.
fn just_outside(p: Param) -> BoxedStrategy<f32> {
    let r = p.range();
    let below = f32::from_bits(if r.min == 0.0 {
        0x8000_0001
    } else {
        r.min.to_bits() - 1
    });
    let above = f32::from_bits(r.max.to_bits() + 1);
    let mut values = vec![below, above, f32::NAN, f32::INFINITY, f32::NEG_INFINITY];
    if r.integer {
        values.push(r.min + 0.5);
    }
    proptest::sample::select(values).boxed()
}

/// SET_PARAM of any parameter with a value in range, just outside, or any.
fn any_set_param() -> impl Strategy<Value = (Param, f32)> {
    (1u8..=16)
        .prop_map(|id| Param::from_u8(id).unwrap())
        .prop_flat_map(|p| {
            let v = prop_oneof![in_range(p), just_outside(p), any_value(p)];
            (Just(p), v)
        })
}

/// Whether the documented rule (`param.rs`: finite, `min..=max` inclusive,
/// whole for the integer parameters) accepts `v`, stated here on its own so
/// the property does not take the decoder's word for it.
fn documented_accepts(p: Param, v: f32) -> bool {
    let r = p.range();
    v.is_finite() && r.min <= v && v <= r.max && (!r.integer || v.fract() == 0.0)
}

/// The payload of the one frame `bytes` holds, through the firmware's parser.
fn parse_one(bytes: &[u8]) -> Vec<u8> {
    let mut p = Parser::new(50);
    let mut payload = None;
    for &b in bytes {
        if let Some(Event::Frame(f)) = p.push(b, 0) {
            payload = Some(f.to_vec());
        }
    }
    payload.expect("a whole frame parses")
}

proptest! {
    /// Every command other than SET_PARAM survives frame -> parse -> decode
    /// unchanged.
    #[test]
    fn commands_round_trip(cmd in any_valid_command()) {
        let payload = parse_one(&frame_of(&cmd));
        prop_assert_eq!(Command::decode(&payload), Ok(cmd));
    }

    /// SET_PARAM: a value the documented range accepts decodes to the same
    /// parameter and the same bits; any other is refused with OutOfRange
    /// (never another status, never accepted), as the firmware replies.
    #[test]
    fn set_param_round_trips_in_range_and_is_refused_outside((p, v) in any_set_param()) {
        let payload = parse_one(&frame_of(&Command::SetParam(p, v)));
        match Command::decode(&payload) {
            Ok(Command::SetParam(q, w)) => {
                prop_assert!(documented_accepts(p, v), "{:?} = {} accepted", p, v);
                prop_assert_eq!(q, p);
                prop_assert_eq!(w.to_bits(), v.to_bits());
            }
            Ok(other) => prop_assert!(false, "decoded as {:?}", other),
            Err(s) => {
                prop_assert!(!documented_accepts(p, v), "{:?} = {} refused", p, v);
                prop_assert_eq!(s, Status::OutOfRange);
            }
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
