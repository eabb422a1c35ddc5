use dalembert::{AnyScene, Model};
fn main() {
    for s in ["particle", "knife", "knife-eps"] {
        let m = Model::new(AnyScene::new(s, &[]).unwrap());
        println!(
            "{s}: field {} var {} vel {}",
            m.field.len(),
            m.field_var.len(),
            m.velocity.len()
        );
    }
}
