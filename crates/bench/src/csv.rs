//! What the reports' CSV files need: fields quoted where they must be (RFC 4180).

/// Quotes a CSV field that needs it.
pub fn csv_field(s: &str) -> String {
    if s.contains([',', '"', '\n']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}
