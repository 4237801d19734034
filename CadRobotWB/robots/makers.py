_POSTS = {"ABB": "abb_rapid", "KUKA": "kuka_krl", "FANUC": "fanuc_ls", "Yaskawa Motoman": "motoman_inform", "Universal Robots": "ur_script"}
def default_post(maker): return _POSTS.get(maker)
def j23_coupled(maker, model): return False
def controller(maker): return ""
