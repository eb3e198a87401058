//! Values as the results files write them, without the formatting machinery between: a
//! float as `{}` prints it ([`with_plain`]) and a record as the CSV writer writes it
//! ([`push_record`]). Both are tested to the byte against the standard library's
//! `Display` and the `csv` crate's writer.

/// Calls `f` with `x` as `format!("{x}")` prints it: the shortest decimal that reads back
/// as `x`, never in exponent form (`0.0000001`, `1` for `1.0`, `-0`, `NaN`, `inf`),
/// without the formatting machinery and, mostly, without an allocation.
///
/// The shortest digits are ryu's. They are `Display`'s (the shortest that reads back,
/// the closest of those) but for one case: `x` exactly halfway between the two closest
/// (2^-25 = 2.98023223876953125e-8 has two 17-digit neighbours, `...312` and `...313`),
/// where ryu takes the even one and `Display` the one above. [`tie_above`] finds those.
pub(crate) fn with_plain<R>(x: f64, f: impl FnOnce(&str) -> R) -> R {
    if !x.is_finite() {
        return f(if x.is_nan() {
            "NaN"
        } else if x > 0.0 {
            "inf"
        } else {
            "-inf"
        });
    }
    let mut ryu = ryu::Buffer::new();
    let text = ryu.format_finite(x);
    let exponent = text.contains('e');
    if exponent || few_decimal_places(x) {
        let (digits, scale) = decimal(text);
        if tie_above(x.abs(), digits, scale) {
            return f(&laid_out(x.is_sign_negative(), digits + 1, scale));
        }
        if exponent {
            return f(&laid_out(x.is_sign_negative(), digits, scale));
        }
    }
    f(text.strip_suffix(".0").unwrap_or(text))
}

/// Whether `x` (finite) has at most 27 decimal places, as a tie must ([`tie_above`]):
/// `x = m 2^e` has `max(0, -(e + the trailing zeros of m))` of them.
fn few_decimal_places(x: f64) -> bool {
    let (m, e) = binary(x);
    m == 0 || e + m.trailing_zeros() as i32 >= -27
}

/// A finite `x` as `m 2^e` exactly (its sign left out), `m` below 2^53.
fn binary(x: f64) -> (u64, i32) {
    let bits = x.to_bits();
    let (biased, fraction) = (((bits >> 52) & 0x7ff) as i32, bits & ((1 << 52) - 1));
    if biased == 0 {
        (fraction, -1074)
    } else {
        (fraction | (1 << 52), biased - 1075)
    }
}

/// ryu's text of a finite float as `digits x 10^scale` (the sign left out).
fn decimal(text: &str) -> (u64, i32) {
    let (mantissa, exponent) = match text.split_once('e') {
        Some((m, e)) => (m, e.parse::<i32>().expect("ryu writes an integer exponent")),
        None => (text, 0),
    };
    let (mut digits, mut after_point, mut seen_point) = (0u64, 0i32, false);
    for b in mantissa.bytes() {
        match b {
            b'.' => seen_point = true,
            b'0'..=b'9' => {
                digits = digits * 10 + u64::from(b - b'0');
                after_point += i32::from(seen_point);
            }
            _ => {}
        }
    }
    (digits, exponent - after_point)
}

/// Whether `x` (positive) is exactly `digits + 1/2` units of `10^scale`: halfway
/// between the shortest decimal ryu chose and the one above it. Such an `x` has
/// `q = 1 - scale` decimal places and its last digit is 5, so `5^q` divides the
/// integer `x 10^q` (below 10^19): `q <= 27` at most.
fn tie_above(x: f64, digits: u64, scale: i32) -> bool {
    let q = 1 - scale;
    if !(1..=27).contains(&q) || digits >= u64::MAX / 10 {
        return false;
    }
    let halfway = u128::from(digits * 10 + 5);
    let (m, e) = binary(x);
    // x 10^q = m 5^q 2^(e + q), below 2^53 5^27 < 2^116.
    let scaled = u128::from(m) * 5u128.pow(q as u32);
    let shift = e + q;
    if shift >= 0 {
        shift < 64 && scaled.leading_zeros() >= 64 && scaled << shift == halfway
    } else {
        let down = (-shift) as u32;
        down < 128 && scaled.trailing_zeros() >= down && scaled >> down == halfway
    }
}

/// `digits x 10^scale` as `Display` lays a float out: every digit, no exponent, no
/// trailing zeros after the point, no point for an integer.
fn laid_out(negative: bool, mut digits: u64, mut scale: i32) -> String {
    while digits != 0 && digits.is_multiple_of(10) {
        digits /= 10;
        scale += 1;
    }
    let mut buffer = itoa::Buffer::new();
    let digits = buffer.format(digits);
    let len = digits.len() as i32;
    let point = len + scale;
    let mut out = String::with_capacity(digits.len() + point.unsigned_abs() as usize + 3);
    if negative {
        out.push('-');
    }
    if point <= 0 {
        out.push_str("0.");
        out.extend(std::iter::repeat_n('0', (-point) as usize));
        out.push_str(digits);
    } else if point >= len {
        out.push_str(digits);
        out.extend(std::iter::repeat_n('0', (point - len) as usize));
    } else {
        out.push_str(&digits[..point as usize]);
        out.push('.');
        out.push_str(&digits[point as usize..]);
    }
    out
}

/// Whether a CSV field must be quoted: it holds a delimiter, a quote or a line break
/// (the `csv` writer's rule for its default, `QuoteStyle::Necessary`).
fn needs_quotes(field: &[u8]) -> bool {
    field
        .iter()
        .any(|&b| matches!(b, b',' | b'"' | b'\n' | b'\r'))
}

/// Appends one CSV record, newline included, as the `csv` crate's default writer writes
/// it: fields quoted only where they must be (quotes doubled inside), and a record of
/// one empty field (or none) written `""` so that it reads back as a record.
pub(crate) fn push_record<I, T>(out: &mut Vec<u8>, record: I)
where
    I: IntoIterator<Item = T>,
    T: AsRef<[u8]>,
{
    let start = out.len();
    let mut fields = 0usize;
    for field in record {
        let field = field.as_ref();
        if fields > 0 {
            out.push(b',');
        }
        fields += 1;
        if needs_quotes(field) {
            out.push(b'"');
            for &b in field {
                if b == b'"' {
                    out.push(b'"');
                }
                out.push(b);
            }
            out.push(b'"');
        } else {
            out.extend_from_slice(field);
        }
    }
    if fields <= 1 && out.len() == start {
        out.extend_from_slice(b"\"\"");
    }
    out.push(b'\n');
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Random bit patterns of every kind (normal, subnormal, huge, tiny, integral), plus
    /// the edges: each printed as `{}` prints it.
    #[test]
    fn plain_floats_are_printed_as_display_prints_them() {
        let mut edges = vec![
            0.0,
            -0.0,
            1.0,
            -1.0,
            0.1,
            0.3,
            1.0 / 3.0,
            2.0 / 3.0,
            1e-7,
            1e15,
            1e16,
            1e17,
            1e21,
            1e22,
            1e23,
            123456789012345680.0,
            9007199254740993.0,
            f64::MAX,
            -f64::MAX,
            f64::MIN_POSITIVE,
            -f64::MIN_POSITIVE,
            5e-324,
            -5e-324,
            f64::EPSILON,
            f64::NAN,
            f64::INFINITY,
            f64::NEG_INFINITY,
            12345.678,
            0.000123,
            100.0,
            1.5,
        ];
        for k in -1074..=1023 {
            edges.push(2f64.powi(k));
            edges.push(2f64.powi(k) * 3.0);
        }
        // Exact halves of short decimals: odd multiples of small powers of two.
        for k in 1..=64 {
            for m in (1..4096u64)
                .step_by(2)
                .chain((1u64 << 52) - 99..(1 << 52) + 99)
            {
                edges.push(m as f64 * 2f64.powi(-k));
            }
        }
        for k in -323..=308 {
            edges.push(format!("1e{k}").parse().unwrap());
            edges.push(format!("9.999999999999999e{k}").parse().unwrap());
        }
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state
        };
        for _ in 0..200_000 {
            let bits = next();
            edges.push(f64::from_bits(bits));
            // Short decimals (rounded measurements, integral values).
            edges.push((bits % 100_000) as f64 / 10f64.powi((bits >> 40) as i32 % 12));
        }
        for x in edges {
            with_plain(x, |text| {
                assert_eq!(text, format!("{x}"), "bits {:#x}", x.to_bits())
            });
        }
    }

    #[test]
    fn records_are_written_as_the_csv_writer_writes_them() {
        let fields = [
            "",
            "plain",
            "a,b",
            "quote \"q\"",
            "line\nbreak",
            "cr\r",
            "é",
            "\"",
            ",",
            " x ",
            "#c",
            "1.5",
        ];
        let mut records: Vec<Vec<&str>> = vec![vec![""], vec!["", ""], vec!["a"], vec![]];
        for (i, a) in fields.iter().enumerate() {
            records.push(vec![a]);
            for b in &fields[i..] {
                records.push(vec![a, b, a]);
            }
        }
        for record in records {
            let mut w = csv::WriterBuilder::new()
                .has_headers(false)
                .from_writer(vec![]);
            w.write_record(&record).unwrap();
            let expected = w.into_inner().unwrap();
            let mut line = Vec::new();
            push_record(&mut line, &record);
            assert_eq!(line, expected, "{record:?}");
        }
    }
}
