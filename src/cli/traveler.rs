//! `tactfab traveler FILE -o DIR`: the run sheet as `DIR/<device>-traveler.md` and `.html`,
//! written as one unit.

use tactfab::report::{build, Options};

use super::args::TravelerArgs;
use super::{check_out, design, origin, write_dir, Outcome, Progress};

pub fn run(args: &TravelerArgs) -> anyhow::Result<Outcome> {
    let (loaded, design) = design(&args.process)?;
    check_out(&args.out, args.replace, &args.process)?;
    let opts = Options {
        origin: origin(&args.process, &loaded),
        fe: (!args.no_fe).then(|| args.accuracy.into()),
        gds_epoch_s: args.date.epoch_s,
        allow_unconverged: args.gate.allow_unconverged,
        verify_solid: None,
    };
    let built = {
        let progress = Progress::new();
        build(&loaded, &design, &opts, &mut |s| progress.stage(s))?
    };
    let (md, html) = built.traveler_names();
    let files = [
        (md.clone(), built.markdown.clone().into_bytes()),
        (html.clone(), built.html.clone().into_bytes()),
    ];
    write_dir(&args.out, &files, args.replace, &args.process)?;
    println!(
        "wrote {} and {}",
        args.out.join(md).display(),
        args.out.join(html).display()
    );
    let failures = built.failures();
    for f in &failures {
        println!("  FAIL: {f}");
    }
    Ok(if failures.is_empty() {
        Outcome::Ok
    } else {
        Outcome::CheckFailed
    })
}
