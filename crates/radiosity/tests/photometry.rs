//! Photometric files end to end: IES LM-63 and EULUMDAT files written here from one known
//! luminaire read back to the same intensities and flux, whatever symmetry they are stored
//! with; the flux integral matches the lumens the files declare; and no input — every
//! truncation of a valid file, token soups, arbitrary bytes — makes a reader panic.
//!
//! The luminaire: I(C, γ) = I₀ cos²γ (1 + 0.3 cos 2C) for γ ≤ 90°, 0 above; symmetric about
//! both principal planes. Its flux is Φ = ∫₀^{2π} ∫₀^{π/2} I sin γ dγ dC = 2π I₀ / 3 (the cos 2C
//! term integrates to zero over a period).

use std::f64::consts::PI;
use std::path::Path;

use glam::DVec3;
use proptest::prelude::*;
use radiosity::photometry::{self, Format, PhotometricFile, Symmetry};

/// I₀, cd.
const I0: f64 = 1200.0;
/// The lamp flux the EULUMDAT files declare (its cd/klm are per 1000 lm of it), lm.
const LAMP_FLUX: f64 = 3000.0;

fn luminaire(c: f64, g: f64) -> f64 {
    if g > 90.0 {
        return 0.0;
    }
    I0 * g.to_radians().cos().powi(2) * (1.0 + 0.3 * (2.0 * c.to_radians()).cos())
}

/// The exact flux of [`luminaire`].
fn exact_flux() -> f64 {
    2.0 * PI * I0 / 3.0
}

/// `from` to `to` in steps of `step`, degrees.
fn steps(from: f64, to: f64, step: f64) -> Vec<f64> {
    (0..=((to - from) / step).round() as usize)
        .map(|k| from + step * k as f64)
        .collect()
}

/// γ of the files: 0–90° by 5°.
fn gammas() -> Vec<f64> {
    steps(0.0, 90.0, 5.0)
}

/// An IES LM-63-2002 file of the luminaire on the horizontal angles `c`, declaring `lumens`;
/// the candela values wrap every 7 values, as writers may.
fn ies_text(c: &[f64], lumens: f64) -> String {
    let g = gammas();
    let list = |v: &[f64]| {
        v.iter()
            .map(|x| format!("{x}"))
            .collect::<Vec<_>>()
            .join(" ")
    };
    let values: Vec<String> = c
        .iter()
        .flat_map(|&ci| g.iter().map(move |&gj| format!("{}", luminaire(ci, gj))))
        .collect();
    let wrapped: Vec<String> = values.chunks(7).map(|w| w.join(" ")).collect();
    format!(
        "IESNA:LM-63-2002\n[TEST] written by tests/photometry.rs\n[MANUFAC] Radiosity\n\
         [LUMINAIRE] cos² wide-narrow downlight\n[LAMP] LED\nTILT=NONE\n\
         1 {lumens} 1 {} {} 1 2 0.6 0.3 0\n1 1 40\n{}\n{}\n{}\n",
        g.len(),
        c.len(),
        list(&g),
        list(c),
        wrapped.join("\n")
    )
}

/// A EULUMDAT file of the luminaire with symmetry `isym` on 16 C planes (22.5°), LORL `lorl` %.
fn ldt_text(isym: u8, lorl: f64) -> String {
    let mc = 16;
    let c_all = steps(0.0, 337.5, 22.5);
    let stored: Vec<usize> = match isym {
        0 => (0..mc).collect(),
        2 => (0..=mc / 2).collect(),
        3 => (3 * mc / 4..=5 * mc / 4).map(|i| i % mc).collect(),
        4 => (0..=mc / 4).collect(),
        _ => unreachable!("the luminaire is not rotationally symmetric"),
    };
    let g = gammas();
    let mut lines: Vec<String> = [
        "Radiosity tests",
        "3",
        &isym.to_string(),
        &mc.to_string(),
        "22.5",
        &g.len().to_string(),
        "5",
        "T-1",
        "cos² wide-narrow downlight",
        "W-1",
        "wide.ldt",
        "2025 / tests",
        "650",
        "350",
        "80",
        "600",
        "300",
        "0",
        "0",
        "0",
        "0",
        "100",
        &lorl.to_string(),
        "1",
        "0",
        "1",
        "2",
        "LED",
        &LAMP_FLUX.to_string(),
        "4000",
        "80",
        "30",
    ]
    .iter()
    .map(|s| s.to_string())
    .collect();
    lines.extend((0..10).map(|_| "0.7".to_string()));
    lines.extend(c_all.iter().map(|c| c.to_string()));
    lines.extend(g.iter().map(|g| g.to_string()));
    for &i in &stored {
        for &gj in &g {
            lines.push(format!(
                "{}",
                luminaire(c_all[i], gj) / (LAMP_FLUX / 1000.0)
            ));
        }
    }
    lines.join("\n") + "\n"
}

fn parse(format: Format, text: &str) -> PhotometricFile {
    let name = match format {
        Format::Ies => "wide.ies",
        Format::Eulumdat => "wide.ldt",
    };
    photometry::parse(format, text, Path::new(name)).unwrap_or_else(|e| panic!("{e}"))
}

/// Directions spread over the sphere (a Fibonacci lattice) and the grid's own angles.
fn directions() -> Vec<DVec3> {
    let n = 500;
    let golden = PI * (3.0 - 5f64.sqrt());
    (0..n)
        .map(|k| {
            let z = 1.0 - 2.0 * (k as f64 + 0.5) / n as f64;
            let r = (1.0 - z * z).sqrt();
            DVec3::new(
                r * (golden * k as f64).cos(),
                r * (golden * k as f64).sin(),
                z,
            )
        })
        .collect()
}

/// Asserts two files describe the same I in every direction and on the grid, to `tol` relative.
fn assert_same(a: &PhotometricFile, b: &PhotometricFile, tol: f64, what: &str) {
    for d in directions() {
        let (x, y) = (a.distribution.intensity(d), b.distribution.intensity(d));
        assert!((x - y).abs() <= tol * I0, "{what}: {d}: {x} vs {y}");
    }
    for c in steps(0.0, 360.0, 22.5) {
        for g in gammas() {
            let (x, y) = (
                a.distribution.intensity_at(c, g),
                b.distribution.intensity_at(c, g),
            );
            assert!(
                (x - y).abs() <= tol * I0,
                "{what}: C {c}, γ {g}: {x} vs {y}"
            );
        }
    }
    assert!(
        (a.distribution.flux() - b.distribution.flux()).abs() <= tol * exact_flux(),
        "{what}"
    );
}

#[test]
fn an_ies_file_stored_with_symmetry_equals_the_full_one() {
    let full = parse(
        Format::Ies,
        &ies_text(&steps(0.0, 360.0, 22.5), exact_flux()),
    );
    assert_eq!(full.symmetry, Symmetry::None);
    for (c, symmetry) in [
        (steps(0.0, 90.0, 22.5), Symmetry::Quadrant),
        (steps(0.0, 180.0, 22.5), Symmetry::PlaneC0C180),
        (steps(90.0, 270.0, 22.5), Symmetry::PlaneC90C270),
        (steps(0.0, 337.5, 22.5), Symmetry::None),
    ] {
        let f = parse(Format::Ies, &ies_text(&c, exact_flux()));
        assert_eq!(f.symmetry, symmetry);
        // The values are printed in full precision: equal up to the last bits of cos.
        assert_same(&full, &f, 1e-12, &format!("{symmetry:?}"));
    }
}

#[test]
fn ies_and_eulumdat_files_of_one_luminaire_agree() {
    let ies = parse(
        Format::Ies,
        &ies_text(&steps(0.0, 90.0, 22.5), exact_flux()),
    );
    for isym in [0, 2, 3, 4] {
        let ldt = parse(Format::Eulumdat, &ldt_text(isym, 100.0));
        // cd/klm × 3000 lm / 1000 rounds once more than the candela: 1e-12 still holds.
        assert_same(&ies, &ldt, 1e-12, &format!("Isym {isym}"));
    }
    let ldt = parse(Format::Eulumdat, &ldt_text(4, 100.0));
    assert_eq!(ies.distribution.peak(), ldt.distribution.peak());
    assert_eq!(ies.distribution.beam_angle(), ldt.distribution.beam_angle());
}

#[test]
fn the_flux_integral_matches_the_declared_lumens() {
    // The grid interpolates cos²γ by chords 5° long: at most h²/8 · max|d²/dγ² cos²γ| = h²/8 · 2
    // below it, h = 0.087 rad, i.e. 1.9e-3 I₀ in the worst spot and less on average; against
    // the mean intensity of the lower hemisphere, Φ/2π = I₀/3, that is a bound of 5.7e-3. In C
    // the 16 evenly spaced planes integrate cos 2C exactly (the trapezoid rule on a period).
    let tolerance = 5.7e-3;
    let ies = parse(
        Format::Ies,
        &ies_text(&steps(0.0, 90.0, 22.5), exact_flux()),
    );
    let phi = ies.distribution.flux();
    let declared = ies.declared_flux().expect("relative photometry");
    assert!(
        (phi - declared).abs() <= tolerance * declared,
        "{phi} vs {declared}"
    );
    // The chord lies below the concave part of cos² near the nadir: the sign says which side.
    assert!(phi != declared);
    // A EULUMDAT file whose light output ratio is the integral's Φ / Φ_lamps.
    let lorl = 100.0 * exact_flux() / LAMP_FLUX;
    let ldt = parse(Format::Eulumdat, &ldt_text(2, lorl));
    let declared = ldt.declared_flux().expect("lamp sets");
    assert!((ldt.distribution.flux() - declared).abs() <= tolerance * declared);
    assert_eq!(ldt.lamp_flux, Some(LAMP_FLUX));
}

#[test]
fn every_truncation_of_a_valid_file_is_an_error() {
    let cases = [
        (Format::Ies, ies_text(&steps(0.0, 90.0, 45.0), 1000.0)),
        (Format::Eulumdat, ldt_text(4, 80.0)),
    ];
    for (format, text) in cases {
        // Cutting into the last number leaves a shorter, valid number: the file is complete
        // once its last token starts.
        let last = text.trim_end().rfind(char::is_whitespace).expect("tokens") + 1;
        for cut in (0..last).filter(|&k| text.is_char_boundary(k)) {
            let r = photometry::parse(format, &text[..cut], Path::new("cut"));
            assert!(r.is_err(), "{format:?} cut at {cut} parsed");
        }
        for cut in (last..=text.len()).filter(|&k| text.is_char_boundary(k)) {
            // No panic; an Ok or an Err, either is fine.
            let _ = photometry::parse(format, &text[..cut], Path::new("cut"));
        }
    }
}

/// Tokens of both formats' vocabularies, for token soups.
const TOKENS: &[&str] = &[
    "IESNA:LM-63-2002",
    "TILT=NONE",
    "TILT=INCLUDE",
    "TILT=x",
    "[TEST]",
    "[MORE]",
    "0",
    "1",
    "2",
    "3",
    "4",
    "-1",
    "90",
    "180",
    "270",
    "360",
    "1e308",
    "-1e308",
    "1e-308",
    "nan",
    "inf",
    "0,5",
    ",",
    "\n",
    "\r\n",
    " ",
    "36001",
    "18446744073709551616",
    "x",
];

proptest! {
    #![proptest_config(ProptestConfig::with_cases(400))]

    #[test]
    fn arbitrary_bytes_never_panic(bytes in proptest::collection::vec(any::<u8>(), 0..400)) {
        let text = String::from_utf8_lossy(&bytes);
        for format in [Format::Ies, Format::Eulumdat] {
            let _ = photometry::parse(format, &text, Path::new("soup"));
        }
    }

    #[test]
    fn token_soups_never_panic(picks in proptest::collection::vec(0..TOKENS.len(), 0..200)) {
        let text: String = picks.iter().map(|&k| TOKENS[k]).collect::<Vec<_>>().join(" ");
        for format in [Format::Ies, Format::Eulumdat] {
            let _ = photometry::parse(format, &text, Path::new("soup"));
        }
    }

    #[test]
    fn valid_files_with_a_token_replaced_never_panic(
        which in 0usize..2000,
        token in 0..TOKENS.len(),
        isym in prop::sample::select(vec![0u8, 2, 3, 4]),
    ) {
        for (format, text) in [
            (Format::Ies, ies_text(&steps(0.0, 90.0, 45.0), 1000.0)),
            (Format::Eulumdat, ldt_text(isym, 80.0)),
        ] {
            // Words with their trailing blank or line end; one word replaced, its end kept.
            let mut words: Vec<String> =
                text.split_inclusive(char::is_whitespace).map(str::to_string).collect();
            let k = which % words.len();
            let end = words[k].chars().last().filter(|c| c.is_whitespace());
            words[k] = format!("{}{}", TOKENS[token], end.map(String::from).unwrap_or_default());
            let mutated = words.concat();
            if let Ok(f) = photometry::parse(format, &mutated, Path::new("mutated")) {
                // What parses is a valid distribution with a finite flux.
                prop_assert!(f.distribution.validate().is_ok());
                prop_assert!(f.distribution.flux().is_finite());
            }
        }
    }
}
