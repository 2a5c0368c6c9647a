//! `rrd_same A.rrd B.rrd`: whether two recordings hold the same content by Rerun's own
//! decoder (the same chunks entity by entity, timelines and values; row and chunk ids
//! ignored) and the same recording id. Exit code 0 if so, 1 with the first difference.
//! `scripts/golden.sh compare` uses it on every `.rrd` of two golden directories.

use std::process::ExitCode;

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [a, b] = args.as_slice() else {
        eprintln!("usage: rrd_same A.rrd B.rrd");
        return ExitCode::from(2);
    };
    let read = |p: &str| whisker_recording::decode::read(std::path::Path::new(p));
    let result = || -> Result<(), Box<dyn std::error::Error>> {
        let ((id_a, chunks_a), (id_b, chunks_b)) = (read(a)?, read(b)?);
        if id_a != id_b {
            return Err(format!("recording ids differ: {id_a} against {id_b}").into());
        }
        Ok(whisker_recording::decode::same_content(
            &chunks_a, &chunks_b,
        )?)
    };
    let result = result();
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("{a} / {b}: {e}");
            ExitCode::FAILURE
        }
    }
}
