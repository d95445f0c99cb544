//! `radiosity info` on luminaires' photometric files: the summary of a valid IES or EULUMDAT
//! file, and one `error: FILE:LINE: CAUSE` line with exit status 2 for a broken one.

use std::fs;
use std::path::Path;
use std::process::Output;

mod common;

use common::{radiosity, scratch};

fn info(dir: &Path, file: &str) -> Output {
    radiosity()
        .args(["info", file])
        .current_dir(dir)
        .output()
        .expect("the binary runs")
}

/// What `radiosity info FILE` prints, once it has succeeded.
fn summary(dir: &Path, file: &str) -> String {
    let out = info(dir, file);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// A Lambertian downlight, I = 1000 cd · cos γ on both principal planes' quadrant: Φ = π · 1000
/// lm, declared as 3141.6 lm of lamps.
fn downlight_ies() -> String {
    let gammas: Vec<String> = (0..=18).map(|k| (5 * k).to_string()).collect();
    let row: Vec<String> = (0..=18)
        .map(|k| format!("{:.4}", 1000.0 * f64::from(5 * k).to_radians().cos()))
        .collect();
    format!(
        "IESNA:LM-63-2002\n[MANUFAC] Radiosity tests\n[LUMINAIRE] Lambertian panel\n[LAMP] LED\n\
         TILT=NONE\n1 3141.6 1 19 3 1 2 0.6 0.3 0\n1 1 36\n{}\n0 45 90\n{}\n{}\n{}\n",
        gammas.join(" "),
        row.join(" "),
        row.join(" "),
        row.join(" ")
    )
}

#[test]
fn info_summarises_an_ies_file() {
    let dir = scratch("info-ies");
    fs::write(dir.join("panel.ies"), downlight_ies()).expect("write");
    let text = summary(&dir, "panel.ies");
    let value = |key: &str| -> String {
        text.lines()
            .find(|l| l.starts_with(key))
            .unwrap_or_else(|| panic!("no `{key}` line in\n{text}"))[14..]
            .to_string()
    };
    assert_eq!(value("format"), "IES LM-63-2002 (type C photometry)");
    assert_eq!(value("luminaire"), "Lambertian panel");
    assert_eq!(value("symmetry"), "about the C0–C180 and C90–C270 planes");
    assert!(
        value("grid").starts_with("3 C planes × 19 γ angles stored; 8 × 19"),
        "{text}"
    );
    // π · 1000 lm less the chord error of cos on 5° steps (h²/4 = 1.9e-3 at most): 3135.6 or
    // more, under 3141.6.
    let flux: f64 = value("flux").split(' ').next().unwrap().parse().unwrap();
    assert!(flux > 3135.6 && flux < 3141.6, "{flux}");
    assert!(
        value("peak").starts_with("1000.0 cd at C 0°, γ 0°"),
        "{text}"
    );
    // cos γ = 1/2 at 60°: a beam of 120° in both planes.
    assert!(
        value("beam angle").starts_with("120.0° in C0–C180, 120.0° in C90–C270"),
        "{text}"
    );
    assert_eq!(
        value("opening"),
        "0.300 × 0.600 × 0.000 m (length × width × height)"
    );
    fs::remove_dir_all(&dir).expect("cleanup");
}

#[test]
fn info_summarises_an_ldt_file() {
    let dir = scratch("info-ldt");
    let mut lines: Vec<String> = [
        "Radiosity tests",
        "1",
        "1",
        "1",
        "0",
        "3",
        "45",
        "R",
        "Dome",
        "D",
        "dome.ldt",
        "today",
        "200",
        "0",
        "50",
        "150",
        "0",
        "0",
        "0",
        "0",
        "0",
        "100",
        "50",
        "1",
        "0",
        "1",
        "1",
        "LED",
        "2000",
        "3000",
        "80",
        "20",
    ]
    .iter()
    .map(|s| s.to_string())
    .collect();
    lines.extend(["0.5"; 10].iter().map(|s| s.to_string()));
    lines.extend(
        ["0", "0", "45", "90", "400", "200", "0"]
            .iter()
            .map(|s| s.to_string()),
    );
    fs::write(dir.join("dome.ldt"), lines.join("\n")).expect("write");
    let text = summary(&dir, "dome.ldt");
    assert!(text.contains("format        EULUMDAT"), "{text}");
    assert!(text.contains("symmetry      rotational"), "{text}");
    // 400 cd/klm × 2000 lm / 1000.
    assert!(
        text.contains("peak          800.0 cd at C 0°, γ 0°"),
        "{text}"
    );
    assert!(
        text.contains("declared      1000.0 lm (lamps 2000.0 lm × light output ratio 0.500)"),
        "{text}"
    );
    assert!(
        text.contains("opening       0.150 × 0.150 × 0.000 m (length × width × height), round"),
        "{text}"
    );
    fs::remove_dir_all(&dir).expect("cleanup");
}

#[test]
fn a_broken_photometric_file_is_one_located_error_and_status_2() {
    let dir = scratch("info-bad");
    // The candela values stop short at line 11: the file announces 3 × 19.
    let text = downlight_ies();
    let cut = text.trim_end().rsplit_once('\n').expect("lines").0;
    fs::write(dir.join("bad.ies"), cut).expect("write");
    fs::write(
        dir.join("type_b.ies"),
        downlight_ies().replace("19 3 1 2", "19 3 2 2"),
    )
    .expect("write");
    for (file, mentions) in [
        (
            "bad.ies",
            "bad.ies:11: expected 57 candela values, found 38 (the file ends)",
        ),
        (
            "type_b.ies",
            "type_b.ies:6: photometric type 2 (type B) is not supported",
        ),
        ("missing.ldt", "missing.ldt: cannot read"),
    ] {
        let out = info(&dir, file);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{file}: {err}");
        assert_eq!(err.lines().count(), 1, "{file}: {err}");
        assert!(err.starts_with("error: "), "{err}");
        assert!(
            err.contains(mentions),
            "{file}: {err:?} does not mention {mentions:?}"
        );
        assert!(out.stdout.is_empty());
    }
    fs::remove_dir_all(&dir).expect("cleanup");
}
