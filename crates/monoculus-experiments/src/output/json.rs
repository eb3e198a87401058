//! JSON values written by hand (summary.json, the replay page's data): strings escaped
//! so that they are also safe inside an HTML `<script>`, non-finite numbers as `null`.

use std::fmt::Write as _;

/// `s` as a JSON string literal, with `<`, `>` and `&` escaped too.
///
/// ```
/// use monoculus_experiments::output::json;
/// assert_eq!(json::string("a\"b</script>"), r#""a\"b\u003c/script\u003e""#);
/// ```
pub fn string(s: &str) -> String {
    let mut out = String::from("\"");
    for c in s.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            '<' => out.push_str("\\u003c"),
            '>' => out.push_str("\\u003e"),
            '&' => out.push_str("\\u0026"),
            c if (c as u32) < 0x20 => {
                let _ = write!(out, "\\u{:04x}", c as u32);
            }
            c => out.push(c),
        }
    }
    out.push('"');
    out
}

/// `x` as a JSON number (the shortest form that reads back to it); `null` if not finite.
///
/// ```
/// use monoculus_experiments::output::json;
/// assert_eq!(json::number(0.5), "0.5");
/// assert_eq!(json::number(f64::NAN), "null");
/// ```
pub fn number(x: f64) -> String {
    if x.is_finite() {
        format!("{x}")
    } else {
        "null".to_string()
    }
}
