//! `hemilab reference`: builds (or keeps) the reference of every scene of a spec.

use crate::cli::ReferenceArgs;
use crate::error::Result;
use crate::io;
use crate::jobs::runner::JobRunner;
use crate::load::load;
use crate::reference::store::{self as refs, Policy};

pub fn run(args: ReferenceArgs) -> Result<()> {
    let loaded = load(&args.spec)?;
    let dir = refs::dir(args.reference_dir.as_deref(), &loaded.spec);
    io::ensure_writable_dir(&dir)?;
    let runner = JobRunner::new(crate::jobs::Threads::resolve(args.common.threads), args.common.quiet)?;
    // A stored reference that serves the spec is kept: for `rays = "auto"` it may hold far more
    // rays than this spec asks (the paper's, shared with a smaller spec), and rebuilding it would
    // throw them away.
    let policy = if args.force { Policy::Rebuild } else { Policy::ReuseOrBuild };
    for (si, scene) in loaded.scenes.iter().enumerate() {
        let kept = policy == Policy::ReuseOrBuild && refs::missing(&loaded.spec, si, scene, &dir)?.is_none();
        let r = crate::jobs::reference::obtain(&loaded.spec, si, scene, &dir, policy, &runner)?;
        println!(
            "{}: noise floor {:.3e} ({} x {} rays){}",
            r.exr.display(),
            r.noise_floor(),
            r.manifest.replicates,
            r.manifest.rays,
            if kept { "; kept, it serves this spec (--force rebuilds it)" } else { "" }
        );
    }
    // The frames of camera paths where the spec measures error.
    let plan = crate::plan::plan(&loaded.spec);
    let si_of = |j: &crate::plan::Job| loaded.scene_of(j).0;
    let views = crate::jobs::reference::obtain_views(
        &loaded.spec,
        &plan,
        &loaded.scenes,
        si_of,
        &dir,
        policy,
        &runner,
    )?;
    if !views.is_empty() {
        println!("{} camera path frame references in {}", views.len(), dir.display());
    }
    runner.bar.finish_and_clear();
    Ok(())
}
