shapegen::generator! {
    struct G;
    shapes: [cube];
    start: A;
    node A {
        params {
            x: f32 = uniform(2.0, 1.0),
            v: vec3 = uniform([0.0, 5.0, 0.0], [1.0, 4.0, 1.0]),
            n: int = uniform(3, 1),
            s: f32 = normal(0.0, -1.0),
            w: choice = choice([0.0, 0.0]),
        }
        |s| {}
    }
}
fn main() {}
