//! Luminances measured on the calibration chart (lab exercise 17), read
//! from CSV, and their normalisation by the maximum as the lab does it.

use std::fmt;

/// One measured patch: its level in [0, 1], the luminance measured on the
/// display (cd/m2) and, optionally, the luminance measured after correction.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Measurement {
    pub level: f64,
    pub luminance: f64,
    pub corrected: Option<f64>,
}

/// What is wrong with a measurement file, and where: `line` counts from 1.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub struct MeasurementError {
    pub line: Option<u64>,
    pub message: String,
}

impl fmt::Display for MeasurementError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.line {
            Some(line) => write!(f, "row {line}: {}", self.message),
            None => f.write_str(&self.message),
        }
    }
}

fn error_at(line: u64, message: impl Into<String>) -> MeasurementError {
    MeasurementError {
        line: Some(line),
        message: message.into(),
    }
}

const COLUMNS: [&str; 3] = ["level", "luminance", "corrected luminance"];

/// At most this many measured rows. The chart has five patches; a file of
/// many thousands is not a measurement, and the fit's time grows with the
/// rows (500,000 took 35 s), so reading stops here.
pub const MAX_ROWS: usize = 10_000;

/// Reads measurements from CSV text: columns level, luminance and optionally
/// the corrected luminance; one optional header row (a first row none of
/// whose values is a number); `#` starts a comment line. Rows are counted as
/// lines of the file, from 1. Spreadsheets in many locales (Polish among
/// them) write `;` between values and a decimal comma: a file whose first
/// row holds a `;` is read that way.
///
/// Levels must differ, and luminances must rise with the level and not be
/// all equal: otherwise no gamma describes them.
pub fn parse_measurements(text: &str) -> Result<Vec<Measurement>, MeasurementError> {
    let semicolons = first_row(text).is_some_and(|row| row.contains(';'));
    let mut reader = csv::ReaderBuilder::new()
        .has_headers(false)
        .flexible(true)
        .trim(csv::Trim::All)
        .comment(Some(b'#'))
        .delimiter(if semicolons { b';' } else { b',' })
        .from_reader(text.as_bytes());
    let mut columns: Option<usize> = None;
    let mut out = Vec::new();
    let mut lines = Vec::new();
    for (index, record) in reader.records().enumerate() {
        let record = record.map_err(|e| {
            let line = e.position().map_or(0, |p| p.line());
            error_at(line, format!("cannot read the CSV: {e}"))
        })?;
        let line = record.position().map_or(index as u64 + 1, |p| p.line());
        // With `;` between values the comma is the decimal point.
        let fields: Vec<String> = record
            .iter()
            .map(|f| {
                if semicolons {
                    f.replace(',', ".")
                } else {
                    f.to_string()
                }
            })
            .collect();
        let fields: Vec<&str> = fields.iter().map(String::as_str).collect();
        if index == 0 && fields.iter().all(|f| f.parse::<f64>().is_err()) {
            columns = Some(check_header_width(line, fields.len())?);
            continue;
        }
        if out.len() == MAX_ROWS {
            return Err(error_at(
                line,
                format!("expected at most {MAX_ROWS} measured rows (the chart has 5 patches)"),
            ));
        }
        let width = match columns {
            Some(width) => width,
            None => *columns.insert(check_header_width(line, fields.len())?),
        };
        out.push(parse_row(line, &fields, width)?);
        lines.push(line);
    }
    check_enough(&out)?;
    check_rising(&out, &lines)?;
    Ok(out)
}

/// The first line that is neither blank nor a comment.
fn first_row(text: &str) -> Option<&str> {
    text.lines()
        .map(str::trim)
        .find(|l| !l.is_empty() && !l.starts_with('#'))
}

/// Two columns (level, luminance) or three (and the corrected luminance).
fn check_header_width(line: u64, n: usize) -> Result<usize, MeasurementError> {
    match n {
        2 | 3 => Ok(n),
        _ => Err(error_at(
            line,
            format!("expected 2 or 3 columns (level, luminance[, corrected luminance]), found {n}"),
        )),
    }
}

/// Most characters of a field a message shows: a field of megabytes (a
/// binary file read as CSV) would otherwise fill the terminal.
const SHOWN_CHARS: usize = 40;

/// A field as a message shows it: its first `SHOWN_CHARS` characters,
/// control characters escaped.
fn shown(text: &str) -> String {
    let count = text.chars().count();
    if count <= SHOWN_CHARS {
        return scene_format::visible::escape_controls(text);
    }
    let start: String = text.chars().take(SHOWN_CHARS).collect();
    format!(
        "{}... ({count} characters)",
        scene_format::visible::escape_controls(&start)
    )
}

fn parse_row(line: u64, fields: &[&str], width: usize) -> Result<Measurement, MeasurementError> {
    if fields.len() > width {
        return Err(error_at(
            line,
            format!("expected {width} values, found {}", fields.len()),
        ));
    }
    let value = |k: usize| -> Result<f64, MeasurementError> {
        let name = COLUMNS[k];
        let text = fields.get(k).copied().unwrap_or("");
        if text.is_empty() {
            return Err(error_at(line, format!("{name}: missing value")));
        }
        match text.parse::<f64>() {
            Ok(x) if x.is_finite() => Ok(x),
            _ => Err(error_at(
                line,
                format!("{name}: expected a number, found `{}`", shown(text)),
            )),
        }
    };
    let level = value(0)?;
    if !(0.0..=1.0).contains(&level) {
        return Err(error_at(
            line,
            format!("level: expected a number from 0 to 1, found {level}"),
        ));
    }
    // 0 is a luminance: an OLED's black, a meter's floor.
    let luminance = |k: usize| -> Result<f64, MeasurementError> {
        let x = value(k)?;
        if x >= 0.0 {
            Ok(x)
        } else {
            Err(error_at(
                line,
                format!(
                    "{}: expected a luminance of 0 or more (cd/m2), found {x}",
                    COLUMNS[k]
                ),
            ))
        }
    };
    Ok(Measurement {
        level,
        luminance: luminance(1)?,
        corrected: if width == 3 {
            Some(luminance(2)?)
        } else {
            None
        },
    })
}

fn check_enough(rows: &[Measurement]) -> Result<(), MeasurementError> {
    let whole = |message: &str| MeasurementError {
        line: None,
        message: message.to_string(),
    };
    if rows.len() < 2 {
        return Err(whole(&format!(
            "expected at least 2 measured rows, found {}",
            rows.len()
        )));
    }
    // Normalised by its largest value, a column of zeros would be 0 / 0.
    if rows.iter().all(|m| m.corrected == Some(0.0)) {
        return Err(whole(
            "every corrected luminance is 0; expected the patches' luminances measured on the corrected chart",
        ));
    }
    if !rows.iter().any(|m| m.level > 0.0 && m.level < 1.0) {
        return Err(whole(
            "expected at least one level strictly between 0 and 1; at 0 and 1 every gamma fits alike",
        ));
    }
    Ok(())
}

/// Levels measured once each; luminances that rise with the level (a
/// display that gets darker as the level rises, or does not change, is a
/// mistake in the file, not a gamma).
fn check_rising(rows: &[Measurement], lines: &[u64]) -> Result<(), MeasurementError> {
    let mut order: Vec<usize> = (0..rows.len()).collect();
    order.sort_by(|&a, &b| rows[a].level.total_cmp(&rows[b].level));
    for pair in order.windows(2) {
        let (a, b) = (&rows[pair[0]], &rows[pair[1]]);
        let (la, lb) = (lines[pair[0]], lines[pair[1]]);
        let (first, second) = (la.min(lb), la.max(lb));
        if a.level == b.level {
            return Err(error_at(
                second,
                format!(
                    "level {} is measured twice (rows {first} and {second}); expected one row per level",
                    a.level
                ),
            ));
        }
        if b.luminance < a.luminance {
            return Err(error_at(
                lb,
                format!(
                    "luminance {} at level {} is below {} at level {} (row {la}); expected luminances that rise with the level",
                    b.luminance, b.level, a.luminance, a.level
                ),
            ));
        }
    }
    let first = rows[0].luminance;
    if rows.iter().all(|m| m.luminance == first) {
        return Err(MeasurementError {
            line: None,
            message: format!(
                "every luminance is {first}; expected luminances that rise with the level (a constant display has no gamma)"
            ),
        });
    }
    Ok(())
}

/// Values divided by their maximum (the lab's normalisation).
pub fn normalise(values: &[f64]) -> Vec<f64> {
    let max = values.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    values.iter().map(|v| v / max).collect()
}

/// (level, luminance / max luminance) of the rows where `value` has one.
pub fn normalised_points(
    rows: &[Measurement],
    value: impl Fn(&Measurement) -> Option<f64>,
) -> Vec<(f64, f64)> {
    let pairs: Vec<(f64, f64)> = rows
        .iter()
        .filter_map(|m| value(m).map(|v| (m.level, v)))
        .collect();
    let ys: Vec<f64> = pairs.iter().map(|p| p.1).collect();
    pairs
        .iter()
        .zip(normalise(&ys))
        .map(|(&(x, _), y)| (x, y))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn measurements_are_normalised_by_their_maximum() {
        let text = "level,luminance\n0,0.5\n0.5,25\n1,100\n";
        let rows = parse_measurements(text).unwrap();
        let points = normalised_points(&rows, |m| Some(m.luminance));
        assert_eq!(points, [(0.0, 0.005), (0.5, 0.25), (1.0, 1.0)]);
    }

    #[test]
    fn a_header_a_corrected_column_and_comments_are_read() {
        let text = "# measured on the lab display\nlevel, luminance, corrected\n\
                    0, 0.4, 0.4\n0.5, 50, 120\n\n1, 250, 249\n";
        let rows = parse_measurements(text).unwrap();
        assert_eq!(rows.len(), 3);
        assert_eq!(
            rows[1],
            Measurement {
                level: 0.5,
                luminance: 50.0,
                corrected: Some(120.0)
            }
        );
    }

    fn error_of(text: &str) -> String {
        parse_measurements(text).unwrap_err().to_string()
    }

    #[test]
    fn a_huge_field_is_shown_cut_short() {
        let huge = "x".repeat(5 << 20);
        let message = error_of(&format!("0,1\n0.5,{huge}\n1,9\n"));
        assert_eq!(
            message,
            format!(
                "row 2: luminance: expected a number, found `{}... (5242880 characters)`",
                "x".repeat(40)
            )
        );
        assert_eq!(
            error_of("0,1\n0.5,\u{1b}[2J\n1,9\n"),
            "row 2: luminance: expected a number, found `\\u{1b}[2J`"
        );
    }

    #[test]
    fn bad_rows_are_named() {
        assert_eq!(
            error_of("level,luminance\n0,1\n0.5,abc\n1,9\n"),
            "row 3: luminance: expected a number, found `abc`"
        );
        assert_eq!(
            error_of("0,1,1\n0.5,2\n1,9,9\n"),
            "row 2: corrected luminance: missing value"
        );
        assert_eq!(
            error_of("0,1\n0.5,\n1,9\n"),
            "row 2: luminance: missing value"
        );
        assert_eq!(
            error_of("0,1\n0.5,-3\n1,9\n"),
            "row 2: luminance: expected a luminance of 0 or more (cd/m2), found -3"
        );
        assert_eq!(
            error_of("0,0,0\n0.5,2,0\n1,9,0\n"),
            "every corrected luminance is 0; expected the patches' luminances measured on the corrected chart"
        );
        // A black patch of 0 is measured, and fits.
        let rows = parse_measurements("0,0\n0.5,0.25\n1,1\n").unwrap();
        let fit = crate::gamma_fit::fit_measurements(&rows).unwrap();
        assert!((fit.gamma - 2.0).abs() < 1e-6, "{fit:?}");
        // Comment and blank lines count: the row is the file's line.
        assert_eq!(
            error_of("# display A\n\n0,1\n0.5,x\n"),
            "row 4: luminance: expected a number, found `x`"
        );
        assert_eq!(
            error_of("0,1\n1.5,3\n"),
            "row 2: level: expected a number from 0 to 1, found 1.5"
        );
        assert_eq!(
            error_of("0,1\n0.5,3,4,5\n"),
            "row 2: expected 2 values, found 4"
        );
        assert_eq!(
            error_of("level\n0\n"),
            "row 1: expected 2 or 3 columns (level, luminance[, corrected luminance]), found 1"
        );
    }

    #[test]
    fn too_few_points_are_refused() {
        assert_eq!(
            error_of("level,luminance\n0.5,10\n"),
            "expected at least 2 measured rows, found 1"
        );
        assert_eq!(error_of(""), "expected at least 2 measured rows, found 0");
        assert!(error_of("0,1\n1,9\n").contains("strictly between 0 and 1"));
    }

    #[test]
    fn semicolons_and_decimal_commas_are_read() {
        // What a spreadsheet in a Polish locale saves as CSV.
        let text = "poziom;luminancja;po korekcji\n0;0,42;0,41\n0,5;50,6;124,9\n1;249,8;249,6\n";
        let rows = parse_measurements(text).unwrap();
        assert_eq!(
            rows[1],
            Measurement {
                level: 0.5,
                luminance: 50.6,
                corrected: Some(124.9)
            }
        );
        assert_eq!(
            error_of("0;1\n0,5;abc\n1;9\n"),
            "row 2: luminance: expected a number, found `abc`"
        );
    }

    #[test]
    fn a_first_row_with_a_number_is_data_not_a_header() {
        // Before, `x` as the first value made the row a header, silently.
        assert_eq!(
            error_of("0,abc\n0.5,3\n1,9\n"),
            "row 1: luminance: expected a number, found `abc`"
        );
        assert_eq!(
            error_of("zero,1\n0.5,3\n1,9\n"),
            "row 1: level: expected a number, found `zero`"
        );
    }

    #[test]
    fn duplicate_levels_are_refused() {
        assert_eq!(
            error_of("0,1\n0.5,20\n1,90\n0.5,22\n"),
            "row 4: level 0.5 is measured twice (rows 2 and 4); expected one row per level"
        );
    }

    #[test]
    fn luminances_must_rise_with_the_level() {
        assert_eq!(
            error_of("0,1\n0.5,50\n1,9\n"),
            "row 3: luminance 9 at level 1 is below 50 at level 0.5 (row 2); expected luminances that rise with the level"
        );
        // Order in the file does not matter, only the levels'.
        assert!(parse_measurements("1,90\n0,1\n0.5,20\n").is_ok());
        assert_eq!(
            error_of("0,7\n0.5,7\n1,7\n"),
            "every luminance is 7; expected luminances that rise with the level (a constant display has no gamma)"
        );
    }

    #[test]
    fn rows_beyond_the_cap_are_refused_without_reading_on() {
        let mut text = String::from("level,luminance\n");
        for k in 0..500_000u32 {
            let x = f64::from(k) / 500_000.0;
            text.push_str(&format!("{x},{}\n", 1.0 + x * x * 100.0));
        }
        assert_eq!(
            error_of(&text),
            format!(
                "row {}: expected at most 10000 measured rows (the chart has 5 patches)",
                MAX_ROWS + 2
            )
        );
        let capped: String = text
            .lines()
            .take(MAX_ROWS + 1)
            .map(|l| format!("{l}\n"))
            .collect();
        assert_eq!(parse_measurements(&capped).unwrap().len(), MAX_ROWS);
    }
}
