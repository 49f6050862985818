//! The printf-style file name patterns of NRRD's `data file: <format>
//! <min> <max> <step>` (`slice%03d.raw`): one integer conversion, written
//! here rather than pulling in a printf crate for one `%d`.

/// Writes `n` into the printf `format`, which holds exactly one integer
/// conversion (`%d`, `%i` or `%u`, with optional `0`, `-`, `+` or space
/// flags and a width); `%%` is a percent sign.
pub(crate) fn format_number(format: &str, n: i64) -> Result<String, String> {
    let bad = || format!("bad 'data file' format '{format}' (need one %d)");
    let mut out = String::new();
    let mut chars = format.chars().peekable();
    let mut done = false;
    while let Some(c) = chars.next() {
        if c != '%' {
            out.push(c);
            continue;
        }
        if chars.peek() == Some(&'%') {
            chars.next();
            out.push('%');
            continue;
        }
        if done {
            return Err(bad());
        }
        let (mut zero, mut left, mut plus) = (false, false, false);
        while let Some(&f) = chars.peek() {
            match f {
                '0' => zero = true,
                '-' => left = true,
                '+' => plus = true,
                ' ' => {}
                _ => break,
            }
            chars.next();
        }
        let mut width = 0usize;
        while let Some(d) = chars.peek().and_then(|c| c.to_digit(10)) {
            width = width.saturating_mul(10).saturating_add(d as usize).min(64);
            chars.next();
        }
        if !matches!(chars.next(), Some('d' | 'i' | 'u')) {
            return Err(bad());
        }
        let sign = if n < 0 {
            "-"
        } else if plus {
            "+"
        } else {
            ""
        };
        let digits = n.unsigned_abs().to_string();
        let pad = width.saturating_sub(sign.len() + digits.len());
        if left {
            out.push_str(&format!("{sign}{digits}{}", " ".repeat(pad)));
        } else if zero {
            out.push_str(&format!("{sign}{}{digits}", "0".repeat(pad)));
        } else {
            out.push_str(&format!("{}{sign}{digits}", " ".repeat(pad)));
        }
        done = true;
    }
    if done {
        Ok(out)
    } else {
        Err(bad())
    }
}
