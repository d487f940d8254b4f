//! Where in a TOML file a key is: the line and column a scene error
//! points at.

pub(super) fn line_col(text: &str, offset: usize) -> (usize, usize) {
    let before = &text[..offset.min(text.len())];
    let line = before.matches('\n').count() + 1;
    let col = before.rfind('\n').map_or(offset, |p| offset - p - 1) + 1;
    (line, col)
}

/// Where a validation error about `key` points: for a message about
/// `plan[k]`, the key inside the k-th `[[plan]]` segment (or that segment's
/// header when the key is missing there); otherwise the first `key`.
pub(super) fn locate_error(text: &str, key: &str, message: &str) -> Option<(usize, usize)> {
    let segment = message
        .strip_prefix("plan[")
        .and_then(|r| r.split(']').next())
        .and_then(|k| k.parse::<usize>().ok());
    if let Some(k) = segment {
        let lines: Vec<&str> = text.lines().collect();
        let starts: Vec<usize> = (0..lines.len())
            .filter(|&i| lines[i].trim().starts_with("[[plan]]"))
            .collect();
        if let Some(&start) = starts.get(k) {
            // The segment runs to the next header that is not a sub-table
            // of this segment.
            let end = (start + 1..lines.len())
                .find(|&i| {
                    let t = lines[i].trim();
                    t.starts_with('[') && !t.starts_with("[plan.")
                })
                .unwrap_or(lines.len());
            let body = lines[start..end].join("\n");
            return Some(locate_key(&body, key).map_or((start + 1, 1), |(l, c)| (start + l, c)));
        }
    }
    Some(locate_dotted(text, key))
}

/// The name of a table header line (`[vehicle]`, `[ plan.position ]  # c`
/// → `vehicle`, `plan.position`), `None` for other lines; arrays of tables
/// (`[[plan]]`) keep one pair of brackets off.
fn header_name(line: &str) -> Option<String> {
    let t = line.split('#').next().unwrap_or_default().trim();
    let inner = t.strip_prefix('[')?.strip_suffix(']')?;
    let inner = inner
        .strip_prefix('[')
        .and_then(|i| i.strip_suffix(']'))
        .unwrap_or(inner);
    Some(
        inner
            .split('.')
            .map(str::trim)
            .collect::<Vec<_>>()
            .join("."),
    )
}

/// Where `key` (`table.name`, or a top-level `name`) is set: `name =` in
/// the `[table]` section (top-level keys: before the first header), else a
/// table header naming the key itself (`[vehicle.params]`), else a dotted
/// `table.name =` or an inline `table = { name = … }`, else the `[table]`
/// header (the key is absent and its default failed a check), else the
/// first `name =` anywhere, else the file's start.
fn locate_dotted(text: &str, key: &str) -> (usize, usize) {
    let (table, name) = key.rsplit_once('.').unwrap_or(("", key));
    let lines: Vec<&str> = text.lines().collect();
    let headers: Vec<(usize, String)> = lines
        .iter()
        .enumerate()
        .filter_map(|(i, l)| header_name(l).map(|n| (i, n)))
        .collect();
    let section = if table.is_empty() {
        Some(0)
    } else {
        headers.iter().find(|(_, n)| n == table).map(|(i, _)| i + 1)
    };
    if let Some(start) = section {
        let end = headers
            .iter()
            .map(|(i, _)| *i)
            .find(|&i| i >= start)
            .unwrap_or(lines.len());
        let body = lines[start..end].join("\n");
        if let Some((l, c)) = locate_key(&body, name).filter(|(l, _)| *l <= end - start) {
            return (start + l, c);
        }
    }
    if let Some((i, _)) = headers.iter().find(|(_, n)| n == key) {
        return (i + 1, 1);
    }
    if !table.is_empty() {
        if let Some(p) = locate_key(text, key) {
            return p;
        }
        let last = table.rsplit('.').next().unwrap_or(table);
        for (i, l) in lines.iter().enumerate() {
            if let Some((lhs, rhs)) = l.split_once('=')
                && lhs.trim() == last
                && rhs.contains(name)
            {
                return (i + 1, l.len() - l.trim_start().len() + 1);
            }
        }
        if let Some(start) = section {
            return (start, 1);
        }
    }
    locate_key(text, name).unwrap_or((1, 1))
}

/// First `key =` in the text (the dotted context is in the message).
fn locate_key(text: &str, key: &str) -> Option<(usize, usize)> {
    let is_ident = |c: char| c.is_ascii_alphanumeric() || c == '_' || c == '-';
    // `key = …` at the start of a line, then anywhere in one (an inline
    // table), then a table header ending in the key (`[vehicle.params]`).
    let assignment = |line: &str, from_start: bool| -> Option<usize> {
        let mut search = 0;
        while let Some(off) = line[search..].find(key) {
            let at = search + off;
            let before_ok = line[..at].chars().next_back().is_none_or(|c| !is_ident(c));
            let rest = &line[at + key.len()..];
            if before_ok
                && rest.trim_start().starts_with('=')
                && (!from_start || line[..at].trim().is_empty())
            {
                return Some(at);
            }
            search = at + key.len();
        }
        None
    };
    for from_start in [true, false] {
        for (i, line) in text.lines().enumerate() {
            if let Some(at) = assignment(line, from_start) {
                return Some((i + 1, line[..at].chars().count() + 1));
            }
        }
    }
    for (i, line) in text.lines().enumerate() {
        let t = line.trim();
        if t.starts_with('[') {
            let name = t.trim_matches(|c| c == '[' || c == ']').trim();
            if name
                .rsplit('.')
                .next()
                .is_some_and(|last| last.trim() == key)
            {
                return Some((i + 1, line.len() - line.trim_start().len() + 1));
            }
        }
    }
    None
}
