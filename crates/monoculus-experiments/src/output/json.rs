//! JSON as monoculus writes it (summary.json, the replay page's data): serde_json's,
//! made safe to embed in an HTML `<script>` element. `<`, `>` and `&` are written
//! `\u003c`, `\u003e` and `\u0026` (only a string can hold them, and JSON reads the
//! escapes back as the same characters), so that no value can close the element; a
//! number that is not finite is `null`, as serde_json writes it.

use serde::Serialize;

/// `value` as compact JSON, safe inside a `<script>` element.
///
/// ```
/// use monoculus_experiments::output::json;
///
/// #[derive(serde::Serialize)]
/// struct Named<'a> {
///     name: &'a str,
///     score: f64,
/// }
///
/// let written = json::to_string(&Named { name: "a\"b</script>", score: f64::NAN });
/// assert_eq!(written, r#"{"name":"a\"b\u003c/script\u003e","score":null}"#);
/// ```
pub fn to_string<T: Serialize + ?Sized>(value: &T) -> String {
    script_safe(serde_json::to_string(value).expect("a report serialises to JSON"))
}

/// `value` as JSON indented by two spaces, with a final line break, safe inside a
/// `<script>` element.
///
/// ```
/// use monoculus_experiments::output::json;
///
/// let written = json::to_string_pretty(&[("found", true)]);
/// assert_eq!(written, "[\n  [\n    \"found\",\n    true\n  ]\n]\n");
/// ```
pub fn to_string_pretty<T: Serialize + ?Sized>(value: &T) -> String {
    let mut s =
        script_safe(serde_json::to_string_pretty(value).expect("a report serialises to JSON"));
    s.push('\n');
    s
}

fn script_safe(json: String) -> String {
    if !json.contains(['<', '>', '&']) {
        return json;
    }
    json.replace('<', "\\u003c")
        .replace('>', "\\u003e")
        .replace('&', "\\u0026")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn what_is_written_reads_back_as_it_was() {
        let names = ["</script>", "a & b", "<!--", "\"quoted\"\n\\", "\u{1}é"];
        let written = to_string(&names);
        assert!(!written.contains(['<', '>', '&']), "{written}");
        let read: Vec<String> = serde_json::from_str(&written).unwrap();
        assert_eq!(read, names);
    }
}
