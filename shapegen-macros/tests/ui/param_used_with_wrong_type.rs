shapegen::generator! {
    struct G;
    shapes: [cube];
    start: A;
    node A emits {
        params { k: vec3 = uniform([1.0; 3], [2.0; 3]) }
        |mut s| {
            s.move_x(k);
            emit!(cube, s.instance());
        }
    }
}
fn main() {}
