shapegen::generator! {
    struct G;
    shapes: [cube];
    start: A;
    node A emits {
        slots { next: A = 0.5 }
        |s| {
            emit!(sphere, s.instance());
            child!(nxt, s);
        }
    }
}
fn main() {}
