//! Writes `FILE.pack` beside each BVH `FILE` named: the packed form the page downloads instead of
//! the file (src/bvh/pack.rs), which unpacks to the same bytes. Refuses, saying why, a file that
//! would not come back byte for byte. Run after changing the bundled sample:
//!
//! ```text
//! cargo run --example pack_bvh -- www/sample.bvh
//! ```

#[cfg(target_arch = "wasm32")]
fn main() {}

#[cfg(not(target_arch = "wasm32"))]
fn main() -> std::process::ExitCode {
    let files: Vec<String> = std::env::args().skip(1).collect();
    if files.is_empty() {
        eprintln!("usage: pack_bvh FILE.bvh…");
        return std::process::ExitCode::FAILURE;
    }
    for file in files {
        let packed = std::fs::read_to_string(&file)
            .map_err(|e| e.to_string())
            .and_then(|text| mocapseg::bvh::pack(&text).map(|p| (text.len(), p)).map_err(|e| e.to_string()))
            .and_then(|(raw, packed)| {
                let out = format!("{file}.pack");
                std::fs::write(&out, &packed).map_err(|e| format!("{out}: {e}"))?;
                Ok(format!("{out}: {} bytes ({raw} unpacked)", packed.len()))
            });
        match packed {
            Ok(line) => println!("{line}"),
            Err(e) => {
                eprintln!("{file}: {e}");
                return std::process::ExitCode::FAILURE;
            }
        }
    }
    std::process::ExitCode::SUCCESS
}
