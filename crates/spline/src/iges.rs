//! IGES 5.3 output: one rational B-spline surface entity (type 128, form 0)
//! per patch, weights 1 and the polynomial flag set, natural parameter
//! bounds, no trimming entities (142/144). Fixed 80-column records with the
//! Start, Global, Directory Entry, Parameter Data and Terminate sections and
//! their sequence numbers.

use crate::atomic::write_atomically;
use crate::error::Result;
use crate::multipatch::Multipatch;
use std::path::Path;

/// A real in IGES form: always a decimal point and an exponent, 17
/// significant digits (reads back to the same `f64`).
fn real(x: f64) -> String {
    format!("{x:.16E}")
}

/// A Hollerith string `nHtext`.
fn hollerith(s: &str) -> String {
    format!("{}H{s}", s.len())
}

/// Packs parameter tokens (each already ending with its delimiter) into
/// lines of at most `width` columns, never splitting a token unless it is
/// longer than a line.
fn pack(tokens: &[String], width: usize) -> Vec<String> {
    let mut lines = vec![String::new()];
    for tok in tokens {
        let cur = lines.last_mut().expect("never empty");
        if cur.len() + tok.len() <= width {
            cur.push_str(tok);
            continue;
        }
        let mut rest = tok.as_str();
        if !cur.is_empty() {
            lines.push(String::new());
        }
        while rest.len() > width {
            lines
                .last_mut()
                .expect("never empty")
                .push_str(&rest[..width]);
            lines.push(String::new());
            rest = &rest[width..];
        }
        lines.last_mut().expect("never empty").push_str(rest);
    }
    lines
}

/// Tokens with delimiters: ',' between, ';' after the last.
fn delimited(fields: Vec<String>) -> Vec<String> {
    let n = fields.len();
    fields
        .into_iter()
        .enumerate()
        .map(|(i, f)| format!("{f}{}", if i + 1 == n { ';' } else { ',' }))
        .collect()
}

/// The UTC time as IGES's `YYYYMMDD.HHNNSS`.
fn timestamp() -> String {
    let secs = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map(|d| d.as_secs() as i64)
        .unwrap_or(0);
    let (days, rem) = (secs.div_euclid(86_400), secs.rem_euclid(86_400));
    // Civil date from days since 1970-01-01 (Howard Hinnant's algorithm).
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = doy - (153 * mp + 2) / 5 + 1;
    let m = if mp < 10 { mp + 3 } else { mp - 9 };
    let y = yoe + era * 400 + i64::from(m <= 2);
    format!(
        "{y:04}{m:02}{d:02}.{:02}{:02}{:02}",
        rem / 3600,
        rem % 3600 / 60,
        rem % 60
    )
}

/// The multipatch as IGES text; `file_name` goes into the Global section.
pub fn to_iges_string(mp: &Multipatch, file_name: &str) -> Result<String> {
    let stamp = timestamp();
    let max_coord = mp
        .points()
        .iter()
        .flat_map(|p| p.iter())
        .fold(0.0f64, |m, x| m.max(x.abs()));
    let global = delimited(vec![
        "1H,".into(),
        "1H;".into(),
        hollerith("quadrille"),
        hollerith(file_name),
        hollerith("quadrille"),
        hollerith(env!("CARGO_PKG_VERSION")),
        "32".into(),
        "38".into(),
        "6".into(),
        "308".into(),
        "15".into(),
        hollerith("quadrille"),
        real(1.0),
        "2".into(),
        hollerith("MM"),
        "1".into(),
        real(1.0),
        hollerith(&stamp),
        real(1e-9),
        real(max_coord.max(1.0)),
        String::new(),
        String::new(),
        "11".into(),
        "0".into(),
        hollerith(&stamp),
        String::new(),
    ]);
    let mut out = String::new();
    let mut line = |data: &str, section: char, seq: usize| {
        out.push_str(&format!("{data:<72}{section}{seq:>7}\n"));
    };
    let start = format!(
        "Quadrille multipatch: {} untrimmed B-spline surfaces (type 128)",
        mp.patches().len()
    );
    line(&start, 'S', 1);
    let glines = pack(&global, 72);
    for (i, g) in glines.iter().enumerate() {
        line(g, 'G', i + 1);
    }
    // Parameter data of every patch.
    let mut params: Vec<Vec<String>> = Vec::new();
    for k in 0..mp.patches().len() {
        let patch = mp.patch(k)?;
        let (ks, kt) = (patch.knots_s(), patch.knots_t());
        let (ns, nt) = (patch.n_s(), patch.n_t());
        let mut f: Vec<String> = vec![
            "128".into(),
            (ns - 1).to_string(),
            (nt - 1).to_string(),
            ks.degree().to_string(),
            kt.degree().to_string(),
            "0".into(),
            "0".into(),
            "1".into(),
            "0".into(),
            "0".into(),
        ];
        f.extend(ks.knots().iter().map(|&x| real(x)));
        f.extend(kt.knots().iter().map(|&x| real(x)));
        f.extend(std::iter::repeat_n(real(1.0), ns * nt));
        // Control points with the s index varying fastest: our row-major order.
        for p in patch.control_points() {
            f.extend(p.iter().map(|&x| real(x)));
        }
        let (s0, s1) = ks.domain();
        let (t0, t1) = kt.domain();
        f.extend([real(s0), real(s1), real(t0), real(t1)]);
        params.push(pack(&delimited(f), 64));
    }
    // Directory entries: two lines per patch.
    let mut pseq = 1;
    for (k, p) in params.iter().enumerate() {
        let d1 = format!(
            "{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}",
            128, pseq, 0, 0, 0, 0, 0, 0, "00000000"
        );
        let d2 = format!(
            "{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}",
            128,
            0,
            0,
            p.len(),
            0,
            "",
            "",
            "PATCH",
            k + 1
        );
        line(&d1, 'D', 2 * k + 1);
        line(&d2, 'D', 2 * k + 2);
        pseq += p.len();
    }
    let mut seq = 1;
    for (k, p) in params.iter().enumerate() {
        for data in p {
            line(&format!("{data:<64}{:>8}", 2 * k + 1), 'P', seq);
            seq += 1;
        }
    }
    let term = format!(
        "S{:>7}G{:>7}D{:>7}P{:>7}",
        1,
        glines.len(),
        2 * params.len(),
        seq - 1
    );
    line(&term, 'T', 1);
    Ok(out)
}

/// Writes the multipatch to `path` as IGES (atomically).
pub fn write_iges(path: &Path, mp: &Multipatch) -> Result<()> {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let text = to_iges_string(mp, &name)?;
    Ok(write_atomically(path, text.as_bytes())?)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::multipatch::tests::two_squares;

    #[test]
    fn records_sections_and_entities() {
        let mp = two_squares(3);
        let text = to_iges_string(&mp, "x.igs").unwrap();
        let lines: Vec<&str> = text.lines().collect();
        assert!(
            lines.iter().all(|l| l.len() == 80),
            "every record is 80 columns"
        );
        // Sections in order, each numbered from 1 without gaps.
        let mut order = String::new();
        let mut counts = std::collections::BTreeMap::new();
        for l in &lines {
            let sec = l.as_bytes()[72] as char;
            let n: usize = l[73..].trim().parse().unwrap();
            let c = counts.entry(sec).or_insert(0);
            *c += 1;
            assert_eq!(n, *c, "sequence of {sec}");
            if !order.ends_with(sec) {
                order.push(sec);
            }
        }
        assert_eq!(order, "SGDPT");
        assert_eq!(counts[&'D'], 4);
        // Only type-128 entities, with the polynomial flag.
        for d in lines.iter().filter(|l| l.as_bytes()[72] == b'D') {
            assert_eq!(d[..8].trim(), "128");
        }
        // The terminate record counts the sections.
        let t = lines.last().unwrap();
        assert_eq!(&t[..8], format!("S{:>7}", counts[&'S']));
        assert_eq!(&t[24..32], format!("P{:>7}", counts[&'P']));
        // The first parameter record: 128, K1 = 5, K2 = 5, M1 = M2 = 3, flags 0,0,1,0,0.
        let p0 = lines.iter().find(|l| l.as_bytes()[72] == b'P').unwrap();
        assert!(p0.starts_with("128,5,5,3,3,0,0,1,0,0,"), "{p0}");
        assert_eq!(p0[64..72].trim(), "1");
        // Real numbers read back exactly: the last four reals of patch 0 are the bounds 0,1,0,1.
        let data: String = lines
            .iter()
            .filter(|l| l.as_bytes()[72] == b'P' && l[64..72].trim() == "1")
            .map(|l| l[..64].trim_end())
            .collect();
        let fields: Vec<&str> = data.trim_end_matches(';').split(',').collect();
        let nums: Vec<f64> = fields[10..].iter().map(|x| x.parse().unwrap()).collect();
        assert_eq!(nums.len(), 2 * 10 + 36 + 36 * 3 + 4);
        assert_eq!(&nums[nums.len() - 4..], &[0.0, 1.0, 0.0, 1.0]);
        let first_cp = &nums[20 + 36..20 + 36 + 3];
        assert_eq!(first_cp, &mp.points()[mp.patches()[0].indices[0]]);
    }

    #[test]
    fn timestamp_shape() {
        let t = timestamp();
        assert_eq!(t.len(), 15);
        assert_eq!(&t[8..9], ".");
        assert!(t[..4].parse::<u32>().unwrap() >= 2024);
    }
}
