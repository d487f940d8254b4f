//! The `lie` bench's medians as tables: against the hand-written twins and
//! against the backends' own types.

use std::collections::BTreeMap;

/// The lie bench's medians as a Markdown table (also printed): against the
/// hand-written twins (ids `<op>/<pair>/<generic|hand>`), or with `native`
/// against the backend's own types (ids
/// `vs-native/<op>/<pair>/<generic|native>`), with the ratio and how many
/// rows are over the 1.10 goal. Returns the table and that count.
pub fn lie_table(rows: &[(String, f64)], native: bool) -> (String, usize) {
    // (op, pair) -> (generic, baseline)
    let mut table: BTreeMap<(String, String), (Option<f64>, Option<f64>)> = BTreeMap::new();
    let base = if native { "native" } else { "hand" };
    for (id, median) in rows {
        let parts: Vec<&str> = id.split('/').collect();
        let (op, pair, kind) = match (native, &parts[..]) {
            (true, ["vs-native", op, pair, kind]) => (op, pair, kind),
            (false, [op, pair, kind]) => (op, pair, kind),
            _ => continue,
        };
        let entry = table.entry((op.to_string(), pair.to_string())).or_default();
        match *kind {
            "generic" => entry.0 = Some(*median),
            k if k == base => entry.1 = Some(*median),
            _ => {}
        }
    }
    if table.is_empty() {
        return (String::new(), 0);
    }
    let what = if native {
        "the backend's own type"
    } else {
        "hand-written"
    };
    let mut md =
        format!("| operation | pair | lie (ns) | {what} (ns) | ratio |\n|---|---|---|---|---|\n");
    let mut over = 0;
    for ((op, pair), (g, h)) in &table {
        let fmt = |x: Option<f64>| x.map_or("–".to_string(), |v| format!("{v:.2}"));
        let ratio = match (g, h) {
            (Some(g), Some(h)) => {
                over += usize::from(g / h > 1.10);
                format!("{:.2}", g / h)
            }
            _ => "–".to_string(),
        };
        md += &format!(
            "| {op} | `{pair}` | {} | {} | {ratio} |\n",
            fmt(*g),
            fmt(*h)
        );
    }
    let with = table.values().filter(|(g, h)| g.is_some() && h.is_some());
    md += &format!(
        "\n{} rows, {} with a baseline, {over} over the 1.10 goal\n",
        table.len(),
        with.count()
    );
    println!("\n{md}");
    (md, over)
}
