//! Arduino's `Print` for the serial ports: every byte goes through
//! [`Serial::write_blocking`], which waits while 63 bytes are queued, as
//! `HardwareSerial::write` does; at 9600 baud a byte leaves every ~1.04 ms.

use crate::hal::usart::{Instance, Serial};

/// `print(const char*)`.
pub fn print_str<U: Instance>(s: &mut Serial<U>, text: &[u8]) {
    for &b in text {
        s.write_blocking(b);
    }
}

/// `println()`: "\r\n".
pub fn println<U: Instance>(s: &mut Serial<U>) {
    print_str(s, b"\r\n");
}

/// `printNumber(n, 10)`: the decimal digits of `n`.
pub fn print_u32<U: Instance>(s: &mut Serial<U>, n: u32) {
    let mut buf = [0u8; 10];
    let mut i = buf.len();
    let mut n = n;
    loop {
        i -= 1;
        if let Some(d) = buf.get_mut(i) {
            *d = b'0' + (n % 10) as u8;
        }
        n /= 10;
        if n == 0 || i == 0 {
            break;
        }
    }
    if let Some(digits) = buf.get(i..) {
        print_str(s, digits);
    }
}

/// `print(long n)` / `print(int n)`: a minus sign, then the magnitude.
pub fn print_i32<U: Instance>(s: &mut Serial<U>, n: i32) {
    if n < 0 {
        s.write_blocking(b'-');
    }
    print_u32(s, n.unsigned_abs());
}

/// `Print::printFloat(number, digits)` in `f32` (the AVR's `double`), in
/// Arduino's order of operations: "nan", "inf", "ovf" beyond +-4294967040,
/// the sign, `number += 0.5 / 10^digits` (divided step by step), the
/// integer part as `unsigned long`, then each decimal as
/// `(unsigned int)(remainder *= 10)`.
pub fn print_f32<U: Instance>(s: &mut Serial<U>, number: f32, digits: u8) {
    if number.is_nan() {
        return print_str(s, b"nan");
    }
    if number.is_infinite() {
        return print_str(s, b"inf");
    }
    if !(-4_294_967_040.0..=4_294_967_040.0).contains(&number) {
        return print_str(s, b"ovf");
    }
    let mut number = number;
    if number < 0.0 {
        s.write_blocking(b'-');
        number = -number;
    }
    let mut rounding: f32 = 0.5;
    for _ in 0..digits {
        rounding /= 10.0;
    }
    number += rounding;
    let int_part = number as u32;
    let mut remainder = number - int_part as f32;
    print_u32(s, int_part);
    if digits > 0 {
        s.write_blocking(b'.');
    }
    for _ in 0..digits {
        remainder *= 10.0;
        let to_print = remainder as u16;
        print_u32(s, to_print as u32);
        remainder -= to_print as f32;
    }
}

/// `println(double)`: two decimals, then "\r\n".
pub fn println_f32<U: Instance>(s: &mut Serial<U>, number: f32) {
    print_f32(s, number, 2);
    println(s);
}

/// `println(int)`.
pub fn println_i32<U: Instance>(s: &mut Serial<U>, n: i32) {
    print_i32(s, n);
    println(s);
}

/// `println(const char*)`.
pub fn println_str<U: Instance>(s: &mut Serial<U>, text: &[u8]) {
    print_str(s, text);
    println(s);
}
