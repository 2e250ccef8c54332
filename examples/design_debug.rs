use shapegen::design::divergence::*;
use shapegen::design::tasks;
use shapegen::design::*;
use shapegen::ops::uncontrolled;
use shapegen::rng::stream;
fn main() {
    for task in tasks::all() {
        if !["S1"].contains(&task.name.as_str()) {
            continue;
        }
        let g = &task.graph;
        let eval: Vec<_> = (0..3000)
            .map(|i| uncontrolled(g, &mut stream(1, &[1, i])).unwrap())
            .collect();
        let target: Vec<f64> = eval.iter().map(|m| task.truth(m)).collect();
        let truth = |m: &shapegen::genome::Chromosome| task.truth(m);
        let mut rng = stream(5, &[]);
        let mut rej = RejectionSampler::new(g, &truth, 1000, &mut rng).unwrap();
        let training: Vec<_> = (0..2000).map(|_| rej.sample(&mut rng).unwrap()).collect();
        let p = parameter_learning(g, &training)
            .unwrap()
            .sampler(g)
            .unwrap();
        let js = |s: &LearnedSampler| {
            let q = weights_from_logs(&eval.iter().map(|m| s.log_ratio(m)).collect::<Vec<_>>());
            let tr: f64 =
                training.iter().map(|m| s.log_ratio(m)).sum::<f64>() / training.len() as f64;
            (jensen_shannon(&target, &q).unwrap(), tr)
        };
        println!("param {:?}", js(&p));
        let wid = g.node_id("W").unwrap();
        let hist = |ms: &mut dyn Iterator<Item = (shapegen::genome::Chromosome, f64)>| {
            let mut h = [0.0f64; 6];
            let mut t = 0.0;
            for (m, w) in ms {
                let c = m.genes(g).filter(|x| x.node() == wid).count().min(5);
                h[c] += w;
                t += w;
            }
            h.iter()
                .map(|x| format!("{:.3}", x / t))
                .collect::<Vec<_>>()
                .join(" ")
        };
        println!(
            "target  {}",
            hist(&mut eval.iter().cloned().zip(target.iter().copied()))
        );
        println!(
            "default {}",
            hist(&mut eval.iter().cloned().map(|m| (m, 1.0)))
        );
        println!(
            "param samples {}",
            hist(&mut (0..5000).map(|i| (p.sample(&mut stream(7, &[i])).unwrap(), 1.0)))
        );
        let qp = weights_from_logs(&eval.iter().map(|m| p.log_ratio(m)).collect::<Vec<_>>());
        println!(
            "param weights {}",
            hist(&mut eval.iter().cloned().zip(qp.iter().copied()))
        );
        let zero = |_: usize, _: usize| 0.0;
        for (rel, k) in [
            (vec![], 1usize),
            (vec![1u16], 1),
            (vec![1u16, 4], 1),
            (vec![], 4),
        ] {
            let opts = StructureOptions {
                max_components: k,
                ..Default::default()
            };
            let dist = |i: usize, j: usize| {
                if k == 1 {
                    zero(i, j)
                } else {
                    ((i % 4) as f64 - (j % 4) as f64).abs()
                }
            };
            let (pdf, rep) = structure_learning(g, &training, &rel, &dist, opts).unwrap();
            let s = pdf.sampler(g).unwrap();
            println!(
                "rel {rel:?} K {k}: {:?} ll {:?}",
                js(&s),
                &rep.log_likelihood[..rep.log_likelihood.len().min(4)]
            );
            println!(
                "   samples {}",
                hist(&mut (0..5000).map(|i| (s.sample(&mut stream(7, &[i])).unwrap(), 1.0)))
            );
            let qs = weights_from_logs(&eval.iter().map(|m| s.log_ratio(m)).collect::<Vec<_>>());
            println!(
                "   weights {}",
                hist(&mut eval.iter().cloned().zip(qs.iter().copied()))
            );
            if rel.len() == 1 && k == 1 {
                println!(
                    "{}",
                    serde_json::to_string(
                        &pdf.components[0]
                            .graph
                            .nodes
                            .iter()
                            .map(|n| (
                                n.name.to_string(),
                                n.slots.iter().map(|s| s.p).collect::<Vec<_>>()
                            ))
                            .collect::<Vec<_>>()
                    )
                    .unwrap()
                );
                println!(
                    "{}",
                    serde_json::to_string(
                        &parameter_learning(g, &training).unwrap().components[0]
                            .graph
                            .nodes
                            .iter()
                            .map(|n| (
                                n.name.to_string(),
                                n.slots.iter().map(|s| s.p).collect::<Vec<_>>()
                            ))
                            .collect::<Vec<_>>()
                    )
                    .unwrap()
                );
            }
        }
    }
}
