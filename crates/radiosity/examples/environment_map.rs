//! Writes the distant light of a Mitsuba scene file (its `constant`, `envmap` or `sunsky`
//! emitter) as a latitude-longitude map in Mitsuba 3's convention: the map that
//! `benches/corpus/reference.py --environment` gives Mitsuba in place of a `sunsky`, so that the
//! reference and our solve see the same sky (Preetham's model and the sun's disc, as
//! `scene::environment` builds them).
//!
//! ```text
//! cargo run --release -p radiosity --example environment_map -- SCENE.xml OUT.exr [WIDTH]
//! ```
//!
//! WIDTH is the map's width in pixels (default 4096; its height is half of it).

use std::path::Path;

use radiosity::io::image_file;
use radiosity::scene::environment::latlong;
use radiosity::scene::import::mitsuba::{self, xml};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [scene, out, rest @ ..] = args.as_slice() else {
        return Err("usage: environment_map SCENE.xml OUT.exr [WIDTH]".into());
    };
    let width: u32 = rest.first().map_or(Ok(4096), |w| w.parse())?;
    if width < 4 {
        return Err("the map must be at least 4 pixels wide".into());
    }
    let doc = xml::read(Path::new(scene))?;
    let version6 = doc.version.starts_with("0.");
    let emitter = doc
        .objects
        .iter()
        .find(|o| o.class == xml::Class::Emitter)
        .ok_or("the file declares no distant emitter")?;
    let distant = mitsuba::environment(emitter, version6)?.distant()?;
    let map = latlong::rasterize(width, &|dir| distant.radiance(dir), distant.disc());
    image_file::write_image(Path::new(out), &map, 0.0)?;
    println!("wrote {out} ({width} x {})", width / 2);
    Ok(())
}
