fn main() {
    let path = std::path::PathBuf::from(std::env::args().nth(1).unwrap());
    let arg = std::env::args().nth(2).unwrap_or("1".into());
    let distance = arg.ends_with('d');
    let samples: u32 = arg.trim_end_matches('d').parse().unwrap();
    let reps: usize = std::env::args().nth(3).map_or(5, |s| s.parse().unwrap());
    let input = tracer_pipeline::Input::File(path);
    let loaded = tracer_pipeline::load(&input).unwrap();
    let scene_format::SceneKind::Scene3d(file) = loaded.kind else {
        panic!()
    };
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    pool.install(|| {
        let scene = tracer_core::Scene::new(tracer_core::prepare::parts(&file).unwrap());
        let mut job = tracer_core::RenderJob::full(&scene).with_samples(samples);
        if distance {
            job = job.with_output(tracer_core::Output::Distance);
        }
        let mut times = vec![];
        for _ in 0..reps {
            let t = std::time::Instant::now();
            let r = tracer_core::render(&scene, &job, &|_| {});
            times.push(t.elapsed().as_secs_f64());
            std::hint::black_box(r);
        }
        times.sort_by(f64::total_cmp);
        println!("min {:.4} med {:.4}", times[0], times[reps / 2]);
    });
}
