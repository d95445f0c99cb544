//! Where the sun is: its direction from a place on Earth, a date and a clock time.
//!
//! The NOAA solar calculator's formulas (Meeus, *Astronomical Algorithms*, 1991, ch. 24 and
//! 27), good to about 0.01° for dates between 1901 and 2099. With T the Julian centuries since
//! J2000.0 of the moment (its Julian day from the date, the clock and its UTC offset):
//!
//! ```text
//! L₀ = 280.46646° + T (36000.76983° + 0.0003032° T)          (mean longitude)
//! M  = 357.52911° + T (35999.05029° − 0.0001537° T)          (mean anomaly)
//! e  = 0.016708634 − T (0.000042037 + 0.0000001267 T)        (orbit's eccentricity)
//! C  = (1.914602° − T (0.004817° + 0.000014° T)) sin M + (0.019993° − 0.000101° T) sin 2M
//!      + 0.000289° sin 3M                                    (equation of centre)
//! λ  = L₀ + C − 0.00569° − 0.00478° sin Ω,  Ω = 125.04° − 1934.136° T   (apparent longitude)
//! ε  = 23.439291° − 0.0130042° T + 0.00256° cos Ω            (obliquity)
//! δ  = asin(sin ε sin λ)                                      (declination)
//! EoT = 4 min/° · (y sin 2L₀ − 2e sin M + 4e y sin M cos 2L₀ − y²/2 sin 4L₀ − 5e²/4 sin 2M),
//!      y = tan²(ε/2), in radians turned to degrees              (equation of time)
//! H  = (60 h_clock + EoT + 4 λ_geo − 60 Δ_UTC) / 4 − 180°      (hour angle, west positive)
//! ```
//!
//! and the sun seen from latitude φ, in the local (east, north, up) frame,
//!
//! ```text
//! s = (−cos δ sin H,  cos φ sin δ − sin φ cos δ cos H,  sin φ sin δ + cos φ cos δ cos H).
//! ```
//!
//! The scene's up is +y; its north is a horizontal direction the scene file gives (−z by
//! default), and east = north × up.

use glam::{DVec3, Vec3};

/// A place and a moment.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Moment {
    /// Latitude, degrees north.
    pub latitude: f64,
    /// Longitude, degrees east.
    pub longitude: f64,
    /// The date (year, month 1–12, day 1–31).
    pub date: (i32, u32, u32),
    /// The local clock time, minutes after midnight.
    pub minutes: f64,
    /// The clock's offset from UTC, hours (1 for CET, −5 for EST).
    pub utc_offset: f64,
}

/// Whether `year` has 366 days.
fn leap(year: i32) -> bool {
    (year % 4 == 0 && year % 100 != 0) || year % 400 == 0
}

/// Days in each month of `year`.
fn month_lengths(year: i32) -> [u32; 12] {
    [
        31,
        if leap(year) { 29 } else { 28 },
        31,
        30,
        31,
        30,
        31,
        31,
        30,
        31,
        30,
        31,
    ]
}

/// `YYYY-MM-DD` as (year, month, day), if it names a day of the Gregorian calendar.
#[must_use]
pub fn parse_date(text: &str) -> Option<(i32, u32, u32)> {
    let mut parts = text.split('-');
    let year: i32 = parts.next()?.parse().ok()?;
    let month: u32 = parts.next()?.parse().ok()?;
    let day: u32 = parts.next()?.parse().ok()?;
    let valid = parts.next().is_none()
        && (1..=12).contains(&month)
        && day >= 1
        && day <= month_lengths(year)[month as usize - 1];
    valid.then_some((year, month, day))
}

/// `HH:MM` (24-hour clock) as minutes after midnight.
#[must_use]
pub fn parse_time(text: &str) -> Option<f64> {
    let (h, m) = text.split_once(':')?;
    let (h, m): (u32, u32) = (h.parse().ok()?, m.parse().ok()?);
    (h < 24 && m < 60).then(|| f64::from(h * 60 + m))
}

impl Moment {
    /// The Julian day of the moment (UTC).
    fn julian_day(&self) -> f64 {
        let (mut year, mut month, day) = self.date;
        if month <= 2 {
            year -= 1;
            month += 12;
        }
        let a = (f64::from(year) / 100.0).floor();
        let b = 2.0 - a + (a / 4.0).floor();
        (365.25 * f64::from(year + 4716)).floor()
            + (30.6001 * f64::from(month + 1)).floor()
            + f64::from(day)
            + b
            - 1524.5
            + (self.minutes - 60.0 * self.utc_offset) / 1440.0
    }

    /// The sun in the local frame (east, north, up), a unit vector (module docs).
    #[must_use]
    pub fn local(&self) -> DVec3 {
        let t = (self.julian_day() - 2_451_545.0) / 36_525.0;
        let l0 = (280.46646 + t * (36_000.769_83 + 0.000_303_2 * t)).to_radians();
        let m = (357.52911 + t * (35_999.050_29 - 0.000_153_7 * t)).to_radians();
        let e = 0.016_708_634 - t * (0.000_042_037 + 0.000_000_126_7 * t);
        let c = (1.914_602 - t * (0.004_817 + 0.000_014 * t)) * m.sin()
            + (0.019_993 - 0.000_101 * t) * (2.0 * m).sin()
            + 0.000_289 * (3.0 * m).sin();
        let omega = (125.04 - 1934.136 * t).to_radians();
        let lambda = l0 + (c - 0.005_69 - 0.004_78 * omega.sin()).to_radians();
        let epsilon = (23.439_291 - 0.013_004_2 * t + 0.002_56 * omega.cos()).to_radians();
        let decl = (epsilon.sin() * lambda.sin()).asin();
        let y = (epsilon / 2.0).tan().powi(2);
        let eot = 4.0
            * (y * (2.0 * l0).sin() - 2.0 * e * m.sin() + 4.0 * e * y * m.sin() * (2.0 * l0).cos()
                - 0.5 * y * y * (4.0 * l0).sin()
                - 1.25 * e * e * (2.0 * m).sin())
            .to_degrees();
        let solar = self.minutes + eot + 4.0 * self.longitude - 60.0 * self.utc_offset;
        let h = (solar / 4.0 - 180.0).to_radians();
        let phi = self.latitude.to_radians();
        DVec3::new(
            -decl.cos() * h.sin(),
            phi.cos() * decl.sin() - phi.sin() * decl.cos() * h.cos(),
            phi.sin() * decl.sin() + phi.cos() * decl.cos() * h.cos(),
        )
    }

    /// The sun's elevation above the horizon, degrees.
    #[must_use]
    pub fn elevation(&self) -> f64 {
        self.local().z.clamp(-1.0, 1.0).asin().to_degrees()
    }

    /// The direction towards the sun in the scene (+y up), `north` the scene's north (made
    /// horizontal and unit here).
    #[must_use]
    pub fn direction(&self, north: Vec3) -> Vec3 {
        let north = Vec3::new(north.x, 0.0, north.z).normalize_or(Vec3::NEG_Z);
        let east = north.cross(Vec3::Y);
        let s = self.local().as_vec3();
        (s.x * east + s.y * north + s.z * Vec3::Y).normalize()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at(latitude: f64, date: (i32, u32, u32), clock: &str) -> Moment {
        Moment {
            latitude,
            longitude: 0.0,
            date,
            minutes: parse_time(clock).unwrap(),
            utc_offset: 0.0,
        }
    }

    /// At solar noon the sun stands 90° − |φ − δ| high: δ = +23.44° at the June solstice
    /// (21 June 2026, 08:24 UTC), −23.44° at the December one (21 December 2026, 20:50 UTC),
    /// 0 at the March equinox (20 March 2026, 14:46 UTC; δ moves 0.4° a day then, so it is
    /// −0.046° at 12:07). Noon on the Greenwich meridian is 12:00 UTC give or take the equation
    /// of time (−1.6 min on 21 June, +7.5 min on 20 March).
    #[test]
    fn the_noon_sun_stands_at_the_latitude_less_the_declination() {
        let june = at(51.5, (2026, 6, 21), "12:00").elevation();
        assert!((june - (90.0 - 51.5 + 23.436)).abs() < 0.02, "{june}");
        let december = at(51.5, (2026, 12, 21), "12:00").elevation();
        assert!(
            (december - (90.0 - 51.5 - 23.436)).abs() < 0.02,
            "{december}"
        );
        let equinox = at(40.0, (2026, 3, 20), "12:07").elevation();
        assert!((equinox - (50.0 - 0.046)).abs() < 0.02, "{equinox}");
    }

    /// The sun rises in the east and sets in the west; at noon it is due south of a northern
    /// place; an hour of clock time is 15° of hour angle, so a place 15° further east whose
    /// clocks run an hour ahead sees the sun where the first place does at the same clock time
    /// (an hour earlier, in which the declination moves by under 0.02°).
    #[test]
    fn the_sun_moves_from_east_to_west_and_clocks_follow_longitude() {
        let north = Vec3::NEG_Z;
        let morning = at(45.0, (2026, 9, 1), "08:00").direction(north);
        let noon = at(45.0, (2026, 9, 1), "12:00").direction(north);
        let evening = at(45.0, (2026, 9, 1), "16:00").direction(north);
        assert!(morning.x > 0.5 && evening.x < -0.5, "{morning} {evening}");
        assert!(noon.z > 0.5 && noon.x.abs() < 0.05, "{noon}");
        let paris = Moment {
            longitude: 15.0,
            utc_offset: 1.0,
            ..at(45.0, (2026, 9, 1), "09:30")
        };
        let greenwich = at(45.0, (2026, 9, 1), "09:30");
        assert!((paris.local() - greenwich.local()).length() < 5e-4);
    }

    #[test]
    fn dates_and_times_are_read_strictly() {
        assert_eq!(parse_date("2024-02-29"), Some((2024, 2, 29)));
        assert_eq!(parse_date("2026-02-29"), None);
        assert_eq!(parse_date("2026-13-01"), None);
        assert_eq!(parse_date("21 June"), None);
        assert_eq!(parse_time("09:30"), Some(570.0));
        assert_eq!(parse_time("24:00"), None);
        assert_eq!(parse_time("9h30"), None);
    }
}
