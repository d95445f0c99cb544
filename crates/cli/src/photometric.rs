//! `radiosity info FILE.ies` / `FILE.ldt`: a luminaire's photometric file in brief.
//!
//! One fact per line: the format and revision, the names the file gives, the symmetry, the grid
//! as stored and as expanded to the whole sphere, the luminous flux Φ = ∫ I dΩ from the
//! interpolated distribution beside the flux the file declares, the maximum intensity and its
//! direction (type C angles), the beam (50 %) and field (10 %) angles in the two principal
//! planes, the luminous opening in metres and the tilt table. The numbers are those of
//! [`radiosity::photometry`], whose module documentation gives the formulas.

use std::path::Path;

use radiosity::photometry::{Format, PhotometricFile, Spread};

/// The report, one fact per line.
pub fn report(path: &Path, f: &PhotometricFile) -> String {
    let d = &f.distribution;
    let mut s = String::new();
    let mut line = |k: &str, v: String| s.push_str(&format!("{k:<14}{v}\n"));
    line("file", path.display().to_string());
    line(
        "format",
        match f.format {
            Format::Ies => format!("IES {} (type C photometry)", f.version),
            Format::Eulumdat => "EULUMDAT (type C photometry)".to_string(),
        },
    );
    for (key, value) in [
        ("manufacturer", &f.manufacturer),
        ("luminaire", &f.luminaire),
        ("lamp", &f.lamp),
    ] {
        if !value.is_empty() {
            line(key, value.clone());
        }
    }
    line("symmetry", f.symmetry.describe().to_string());
    line(
        "grid",
        format!(
            "{} C planes × {} γ angles stored; {} × {} over the sphere",
            f.stored.0,
            f.stored.1,
            d.c_angles().len(),
            d.gamma_angles().len()
        ),
    );
    let flux = d.flux();
    line(
        "flux",
        format!("{flux:.1} lm (∫ I dΩ of the interpolated distribution)"),
    );
    let declared = match (f.lamp_flux, f.output_ratio) {
        (None, _) => "none (absolute photometry)".to_string(),
        (Some(lamps), None) => format!("{lamps:.1} lm of lamps"),
        (Some(lamps), Some(ratio)) => format!(
            "{:.1} lm (lamps {lamps:.1} lm × light output ratio {ratio:.3})",
            lamps * ratio
        ),
    };
    let share = f
        .declared_flux()
        .filter(|v| *v > 0.0)
        .map(|v| format!("; the integral is {:.1} % of it", 100.0 * flux / v))
        .unwrap_or_default();
    line("declared", format!("{declared}{share}"));
    let peak = d.peak();
    line(
        "peak",
        format!("{:.1} cd at C {}°, γ {}°", peak.candela, peak.c, peak.gamma),
    );
    let axis = if peak.gamma > 90.0 { "zenith" } else { "nadir" };
    let spread = |s: Spread, percent: u32| {
        format!(
            "{:.1}° in C0–C180, {:.1}° in C90–C270 (I ≥ {percent} % of the peak, from the {axis})",
            s.c0_c180, s.c90_c270
        )
    };
    line("beam angle", spread(d.beam_angle(), 50));
    line("field angle", spread(d.field_angle(), 10));
    let o = f.opening;
    line(
        "opening",
        format!(
            "{:.3} × {:.3} × {:.3} m (length × width × height){}",
            o.length,
            o.width,
            o.height,
            if o.round { ", round" } else { "" }
        ),
    );
    line(
        "tilt",
        match &f.tilt {
            None => "none".to_string(),
            Some(t) => format!(
                "table of {} angles {}°–{}° (lamp geometry {}), factors {:.3}–{:.3}; applied by \
                 the installation's tilt",
                t.angles.len(),
                t.angles[0],
                t.angles[t.angles.len() - 1],
                t.geometry,
                t.factors.iter().copied().fold(f64::INFINITY, f64::min),
                t.factors.iter().copied().fold(f64::NEG_INFINITY, f64::max),
            ),
        },
    );
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_isotropic_lamp_reports_four_pi_i() {
        let text = "IES:LM-63-2019\n[LUMINAIRE] Bare\nTILT=NONE\n1 1256.637 1 2 1 1 2 0 0 0\n\
                    1 1 5\n0 180\n0\n100 100\n";
        let path = Path::new("bare.ies");
        let f = radiosity::photometry::parse(Format::Ies, text, path).expect("valid");
        let r = report(path, &f);
        assert!(r.contains("format        IES LM-63-2019"), "{r}");
        assert!(r.contains("luminaire     Bare\n"), "{r}");
        assert!(!r.contains("manufacturer"), "{r}");
        // Φ = 4π · 100 cd = 1256.6 lm, as declared.
        assert!(r.contains("flux          1256.6 lm"), "{r}");
        assert!(r.contains("the integral is 100.0 % of it"), "{r}");
        // I never falls below half: the beam reaches 180° from the nadir on each side.
        assert!(r.contains("beam angle    360.0° in C0–C180"), "{r}");
    }
}
