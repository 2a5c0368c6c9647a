//! `whisker assets generate`: writes the generated object catalogue
//! (`whisker_sim::environment::assets`) as OBJ files.

use crate::record::Context;
use std::path::Path;
use whisker_scenario::Result;
use whisker_scenario::files::{create_dir, write_atomic};
use whisker_sim::environment::assets::{CATALOGUE, obj};

/// Writes every catalogued asset to `out/<name>.obj`.
pub fn generate_all(out: &Path, ctx: Context) -> Result {
    create_dir(out)?;
    for asset in &CATALOGUE {
        let text = obj(asset);
        let path = out.join(format!("{}.obj", asset.name));
        write_atomic(&path, text.as_bytes())?;
        let triangles = text.lines().filter(|l| l.starts_with("f ")).count();
        ctx.say(&format!(
            "{:<10} {:>6} triangles  {:.2} x {:.2} x {:.2} m  -> {}",
            asset.name,
            triangles,
            asset.size[0],
            asset.size[1],
            asset.size[2],
            path.display()
        ));
    }
    Ok(())
}
