//! How fast the planar pose cells' packet moves under the full update (attractor dynamics
//! and path integration, `ratslam::posecells3d`) at constant speed, as a fraction of the
//! commanded v·t: the lattice pins a packet moving a fraction of a cell per update, and
//! its spread over θ layers makes it lag at whole cells. Path integration alone is exact
//! (tests/ratslam.rs).
//!
//!   cargo run --release -p whisker-slam --example packet_speed

use whisker_slam::pose_grid::population_index;
use whisker_slam::ratslam::posecells3d::{PlanarCellParams, PoseCells3};

/// The packet's circular centre of mass on the x and y axes (cells).
fn centre(cells: &PoseCells3) -> [f64; 2] {
    let n = cells.params.dim_xy;
    let mut marginals = [vec![0.0; n], vec![0.0; n]];
    for (i, a) in cells.grid.cells.iter().enumerate() {
        let c = cells.grid.coords(i);
        marginals[0][c[0]] += a;
        marginals[1][c[1]] += a;
    }
    [
        population_index(&marginals[0]),
        population_index(&marginals[1]),
    ]
}

fn main() {
    let p = PlanarCellParams {
        dim_xy: 21,
        ..PlanarCellParams::default()
    };
    let n = p.dim_xy as f64;
    let updates = 100;
    println!("speed (cells/update)  heading (deg)  moved / v·t over {updates} updates");
    for v in [0.1, 0.25, 0.37, 0.5, 0.75, 1.0] {
        for layer in [0.0, 4.5] {
            let mut cells = PoseCells3::new(p, &[10.0, 10.0, layer]);
            for _ in 0..30 {
                cells.update(0.0, 0.0);
            }
            let heading = layer * p.cell_angle();
            let mut previous = centre(&cells);
            let mut moved = 0.0;
            for _ in 0..updates {
                cells.update(v * p.cell_size_m, 0.0);
                let now = centre(&cells);
                let step = |a: f64, b: f64| (a - b + n / 2.0).rem_euclid(n) - n / 2.0;
                moved += step(now[0], previous[0]) * heading.cos()
                    + step(now[1], previous[1]) * heading.sin();
                previous = now;
            }
            println!(
                "{v:>20}  {:>13}  {:.4}",
                heading.to_degrees(),
                moved / (v * updates as f64)
            );
        }
    }
}
