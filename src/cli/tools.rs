//! `whisker assets` and `whisker urdf`: the generated meshes and robot descriptions.

use super::print_json;
use std::path::PathBuf;
use whisker_experiments::record::Context;
use whisker_scenario::Result;

/// `whisker assets …`.
#[derive(clap::Subcommand)]
pub enum AssetsCommand {
    /// Generate the object catalogue (deterministic) as OBJ files.
    Generate {
        /// Output directory.
        #[arg(long, default_value = "assets/meshes")]
        out: PathBuf,
    },
}

/// `whisker urdf …`.
#[derive(clap::Subcommand)]
pub enum UrdfCommand {
    /// Links, joints, limits and the default chain.
    Info {
        /// The URDF file.
        urdf: PathBuf,
        /// Directory searched for `package://` meshes (repeatable).
        #[arg(long = "package-path")]
        package_paths: Vec<PathBuf>,
    },
    /// Forward kinematics: the pose of a link in another link's frame.
    Fk {
        /// The URDF file.
        urdf: PathBuf,
        /// Joint positions of the chain from --base to --link, comma-separated (rad; m for prismatic).
        #[arg(long, allow_hyphen_values = true)]
        joints: String,
        /// Frame the pose is expressed in [default: base_link, else the root link].
        #[arg(long)]
        base: Option<String>,
        /// Link whose pose is computed [default: tool0, else the only leaf link].
        #[arg(long)]
        link: Option<String>,
        /// Print one JSON object.
        #[arg(long)]
        json: bool,
        /// Directory searched for `package://` meshes (repeatable).
        #[arg(long = "package-path")]
        package_paths: Vec<PathBuf>,
    },
}

/// `whisker assets generate`.
pub fn assets(command: &AssetsCommand, ctx: Context) -> Result {
    match command {
        AssetsCommand::Generate { out } => whisker_experiments::assets::generate_all(out, ctx),
    }
}

/// `whisker urdf info|fk`.
pub fn urdf(command: &UrdfCommand, ctx: Context) -> Result {
    match command {
        UrdfCommand::Info {
            urdf,
            package_paths,
        } => whisker_experiments::urdf::info(urdf, package_paths, ctx),
        UrdfCommand::Fk {
            urdf,
            joints,
            base,
            link,
            json,
            package_paths,
        } => {
            let fk = whisker_experiments::urdf::fk(
                urdf,
                package_paths,
                joints,
                base.as_deref(),
                link.as_deref(),
            )?;
            match json {
                true => print_json(&fk, true),
                false => print!("{fk}"),
            }
            Ok(())
        }
    }
}
