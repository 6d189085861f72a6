//! Firmware variables read as the Rust types they are: [`Var`], for
//! [`super::Harness::var`] and the typed [`Condition`]s.

use crate::runs::scenario::{Condition, VarType};

/// A type a firmware variable is read as: the integers up to 32 bits,
/// `f32` and `bool` (a byte, true when not 0), little-endian as avr-gcc
/// and rustc lay them out. Sealed: the scenario files' [`VarType`]s are
/// the types the bench reads.
pub trait Var: Copy + PartialEq + std::fmt::Debug + sealed::Sealed {
    /// The scenario type of the same size and reading.
    const TYPE: VarType;
    /// The value of the variable's bytes (`TYPE.size()` of them).
    fn from_bytes(bytes: [u8; 4]) -> Self;
    /// As a number, for the conditions scenario files judge.
    fn to_f64(self) -> f64;
}

mod sealed {
    pub trait Sealed {}
}

macro_rules! vars {
    ($($t:ty => $ty:ident, $n:literal;)*) => {$(
        impl sealed::Sealed for $t {}
        impl Var for $t {
            const TYPE: VarType = VarType::$ty;
            fn from_bytes(b: [u8; 4]) -> Self {
                let mut bytes = [0u8; $n];
                bytes.copy_from_slice(&b[..$n]);
                <$t>::from_le_bytes(bytes)
            }
            fn to_f64(self) -> f64 {
                f64::from(self)
            }
        }
    )*};
}
vars! {
    u8 => U8, 1;
    i8 => I8, 1;
    u16 => U16, 2;
    i16 => I16, 2;
    u32 => U32, 4;
    i32 => I32, 4;
    f32 => F32, 4;
}

impl sealed::Sealed for bool {}
impl Var for bool {
    const TYPE: VarType = VarType::U8;
    fn from_bytes(b: [u8; 4]) -> Self {
        b[0] != 0
    }
    fn to_f64(self) -> f64 {
        f64::from(u8::from(self))
    }
}

impl Condition {
    /// The firmware variable `symbol`, read as `T`, equals `value`:
    /// `Condition::var_eq("HT_STATE", 1u8)`.
    pub fn var_eq<T: Var>(symbol: &str, value: T) -> Self {
        Self::var_between::<T>(symbol, Some(value), None, None, None)
    }

    /// The firmware variable `symbol`, read as `T`, is not `value`:
    /// `Condition::var_ne("HT_FAULT", 0u8)`.
    pub fn var_ne<T: Var>(symbol: &str, value: T) -> Self {
        Self::var_between::<T>(symbol, None, Some(value), None, None)
    }

    /// The firmware variable `symbol`, read as `T`, is `min` or more (when
    /// given) and `max` or less (when given): `Condition::var_in("count",
    /// Some(100i32), None)`.
    pub fn var_in<T: Var>(symbol: &str, min: Option<T>, max: Option<T>) -> Self {
        Self::var_between::<T>(symbol, None, None, min, max)
    }

    fn var_between<T: Var>(
        symbol: &str,
        eq: Option<T>,
        ne: Option<T>,
        min: Option<T>,
        max: Option<T>,
    ) -> Self {
        Condition::Var {
            symbol: symbol.into(),
            ty: T::TYPE,
            eq: eq.map(Var::to_f64),
            ne: ne.map(Var::to_f64),
            min: min.map(Var::to_f64),
            max: max.map(Var::to_f64),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each type reads its own bytes, signed and float as such, and no
    /// byte past its size.
    #[test]
    fn each_type_reads_its_bytes() {
        let b = [0xFE, 0xFF, 0xFF, 0xFF];
        assert_eq!(u8::from_bytes(b), 0xFE);
        assert_eq!(i8::from_bytes(b), -2);
        assert_eq!(u16::from_bytes(b), 0xFFFE);
        assert_eq!(i16::from_bytes(b), -2);
        assert_eq!(u32::from_bytes(b), 0xFFFF_FFFE);
        assert_eq!(i32::from_bytes(b), -2);
        assert_eq!(f32::from_bytes(1.5f32.to_le_bytes()), 1.5);
        assert!(bool::from_bytes([2, 0, 0, 0]));
        assert!(!bool::from_bytes([0, 1, 1, 1]));
        // The sizes agree with the scenario types'.
        assert_eq!(<u16 as Var>::TYPE.size(), 2);
        assert_eq!(<bool as Var>::TYPE.size(), 1);
    }

    /// A typed condition carries its type and its value as a scenario
    /// file's would.
    #[test]
    fn typed_conditions_carry_their_type() {
        assert_eq!(
            Condition::var_ne("HT_FAULT", 0u8),
            Condition::Var {
                symbol: "HT_FAULT".into(),
                ty: VarType::U8,
                eq: None,
                ne: Some(0.0),
                min: None,
                max: None,
            }
        );
        match Condition::var_in("count", Some(-5i32), Some(7)) {
            Condition::Var { ty, min, max, .. } => {
                assert_eq!((ty, min, max), (VarType::I32, Some(-5.0), Some(7.0)));
            }
            other => panic!("{other:?}"),
        }
    }
}
